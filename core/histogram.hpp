#pragma once
// A 1D or 2D histogram over fixed ranges: integer counts in half-open bins [lo, hi), and the
// samples that fall outside counted apart (underflow: below some axis; overflow: otherwise at or
// above some axis, or not a number). Merging adds counts, exact in any order.
#include <cstdint>
#include <string>
#include <vector>

namespace qmaps {

struct Axis {
  std::string coordinate;
  double lo = 0, hi = 1;
  std::int64_t bins = 1;

  // The bin of x: −1 below lo, `bins` at or above hi (or NaN).
  std::int64_t bin(double x) const {
    if (x < lo) return -1;
    if (!(x < hi)) return bins;
    const auto i = static_cast<std::int64_t>((x - lo) * (static_cast<double>(bins) / (hi - lo)));
    return i < bins ? i : bins - 1;
  }
  std::vector<double> edges() const;
};

class Histogram {
 public:
  Histogram() = default;
  Histogram(std::string name, std::vector<Axis> axes);

  // One sample: a value per axis.
  void add(const double* x) {
    ++samples_;
    std::int64_t index = 0;
    bool below = false, above = false;
    for (const Axis& a : axes_) {
      const std::int64_t i = a.bin(*x++);
      below = below || i < 0;
      above = above || i >= a.bins;
      index = index * a.bins + i;
    }
    if (below)
      ++underflow_;
    else if (above)
      ++overflow_;
    else
      ++counts_[static_cast<std::size_t>(index)];
  }
  void merge(const Histogram& other);
  // The same histogram with every count 0 (a thread's partial).
  Histogram empty_copy() const;

  const std::string& name() const { return name_; }
  const std::vector<Axis>& axes() const { return axes_; }
  const std::vector<std::int64_t>& counts() const { return counts_; }  // row-major, x first
  std::int64_t underflow() const { return underflow_; }
  std::int64_t overflow() const { return overflow_; }
  std::int64_t samples() const { return samples_; }

 private:
  std::string name_;
  std::vector<Axis> axes_;
  std::vector<std::int64_t> counts_;
  std::int64_t underflow_ = 0, overflow_ = 0, samples_ = 0;
};

}  // namespace qmaps
