#include "ensembles/program/drift_summary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace qmaps {

DriftSummary::DriftSummary(std::span<const double> initial, std::span<const double> max_abs_drift,
                           std::span<const std::uint8_t> keep) {
  for (std::size_t i = 0; i < initial.size(); ++i) {
    if (!keep.empty() && !keep[i]) continue;
    const double scale = std::fabs(initial[i]);
    // An invariant that is not a number (or infinite) at the start has no drift to speak of.
    const double d = !std::isfinite(scale) ? std::numeric_limits<double>::quiet_NaN()
                     : scale > 0           ? max_abs_drift[i] / scale
                                           : max_abs_drift[i];
    not_numbers_ += std::isnan(d);
    sorted_.push_back(d);
  }
  // NaN after every number: the worst of a set with a NaN is NaN, never a number below it.
  std::sort(sorted_.begin(), sorted_.end(),
            [](double a, double b) { return a < b || (!std::isnan(a) && std::isnan(b)); });
}

double DriftSummary::percentile(double p) const {
  if (sorted_.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(sorted_.size())));
  return sorted_[std::clamp<std::size_t>(rank, 1, sorted_.size()) - 1];
}

}  // namespace qmaps
