#include "ensembles/io/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace qmaps {
namespace {

std::size_t rank_of(double f, std::size_t n) {
  return static_cast<std::size_t>(f * static_cast<double>(n - 1) + 0.5);
}

}  // namespace

double quantile(std::vector<double> values, double f) {
  if (values.empty()) return std::nan("");
  const std::size_t k = rank_of(f, values.size());
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

std::vector<double> quantiles(std::vector<double> values, std::initializer_list<double> ascending) {
  std::vector<double> out;
  auto from = values.begin();  // the ranks below a found one hold nothing above it
  for (const double f : ascending) {
    if (values.empty()) {
      out.push_back(std::nan(""));
      continue;
    }
    const auto at = values.begin() + static_cast<std::ptrdiff_t>(rank_of(f, values.size()));
    std::nth_element(from, at, values.end());
    out.push_back(*at);
    from = at;
  }
  return out;
}

double relative_drift(double initial, double max_abs_drift) {
  const double scale = std::fabs(initial);
  return !std::isfinite(scale) ? std::numeric_limits<double>::quiet_NaN()
         : scale > 0           ? max_abs_drift / scale
                               : max_abs_drift;
}

DriftSummary::DriftSummary(std::span<const double> initial, std::span<const double> max_abs_drift,
                           std::span<const std::uint8_t> keep) {
  for (std::size_t i = 0; i < initial.size(); ++i) {
    if (!keep.empty() && !keep[i]) continue;
    const double d = relative_drift(initial[i], max_abs_drift[i]);
    not_numbers_ += std::isnan(d);
    sorted_.push_back(d);
  }
  // NaN after every number: the worst of a set with a NaN is NaN, never a number below it.
  std::sort(sorted_.begin(), sorted_.end(),
            [](double a, double b) { return a < b || (!std::isnan(a) && std::isnan(b)); });
}

double DriftSummary::quantile(double f) const {
  if (sorted_.empty()) return std::numeric_limits<double>::quiet_NaN();
  return sorted_[rank_of(f, sorted_.size())];
}

}  // namespace qmaps
