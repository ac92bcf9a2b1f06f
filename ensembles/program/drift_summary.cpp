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
    sorted_.push_back(scale > 0 ? max_abs_drift[i] / scale : max_abs_drift[i]);
  }
  std::sort(sorted_.begin(), sorted_.end());
}

double DriftSummary::percentile(double p) const {
  if (sorted_.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(sorted_.size())));
  return sorted_[std::clamp<std::size_t>(rank, 1, sorted_.size()) - 1];
}

}  // namespace qmaps
