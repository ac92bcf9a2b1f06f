#pragma once
// The statistics qmaps reports over orbits, each defined once (docs/hdf5-schema.md, "Statistics"):
//   quantile(values, f)   the value of 0-based rank round(f·(n − 1)) among the n values sorted:
//                         f = 0.5 the median, f = 1 the largest; NaN when there is none
//   relative_drift(I_0, d)  an orbit's relative drift d/|I_0|, d = max|I_n − I_0|: the absolute
//                         drift where I_0 = 0, NaN where I_0 is not finite (nothing to measure by)
// The files' attributes (chaos quartiles, a sweep's medians and worst drift), the drift
// histograms, `qmaps info` and `qmaps check` all use these.
#include <cstdint>
#include <initializer_list>
#include <span>
#include <vector>

namespace qmaps {

double quantile(std::vector<double> values, double f);
// quantile(values, f) for each f of `ascending`, from one copy of the values.
std::vector<double> quantiles(std::vector<double> values, std::initializer_list<double> ascending);
double relative_drift(double initial, double max_abs_drift);

// The orbits' relative drift of one invariant, sorted for its quantiles.
class DriftSummary {
 public:
  // Over the orbits with keep[i] (e.g. never escaped); every orbit when keep is empty.
  DriftSummary(std::span<const double> initial, std::span<const double> max_abs_drift,
               std::span<const std::uint8_t> keep = {});
  std::size_t orbits() const { return sorted_.size(); }
  // The orbits whose drift is not a number (an invariant NaN or infinite): they sort above every
  // number, so that the worst is NaN, never a number below them.
  std::size_t not_numbers() const { return not_numbers_; }
  // quantile(drifts, f), NaN ranked last.
  double quantile(double f) const;

 private:
  std::vector<double> sorted_;
  std::size_t not_numbers_ = 0;
};

}  // namespace qmaps
