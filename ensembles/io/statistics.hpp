#pragma once
// Percentiles of the orbits' relative invariant drift, for `qmaps info` and `qmaps check`.
// An orbit's relative drift is max|I_n − I_0| / |I_0| (the absolute drift where I_0 = 0), NaN
// where I_0 is not finite.
#include <cstdint>
#include <span>
#include <vector>

namespace qmaps {

class DriftSummary {
 public:
  // Over the orbits with keep[i] (e.g. never escaped); every orbit when keep is empty.
  DriftSummary(std::span<const double> initial, std::span<const double> max_abs_drift,
               std::span<const std::uint8_t> keep = {});
  std::size_t orbits() const { return sorted_.size(); }
  // The orbits whose drift is not a number (an invariant NaN or infinite): they sort above every
  // number, so that the worst is NaN, never a number below them.
  std::size_t not_numbers() const { return not_numbers_; }
  // The value below which a fraction p of the orbits lie: the ⌈p n⌉-th smallest (nearest rank);
  // p = 1 is the worst, p = 0.5 the median. NaN when there is no orbit.
  double percentile(double p) const;

 private:
  std::vector<double> sorted_;
  std::size_t not_numbers_ = 0;
};

}  // namespace qmaps
