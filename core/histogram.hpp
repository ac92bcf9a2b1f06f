#pragma once
// A 1D or 2D histogram over fixed ranges: integer counts in half-open bins [lo, hi), and the
// samples that fall outside counted apart (underflow: below some axis; overflow: otherwise at or
// above some axis, or not a number). Merging adds counts, exact in any order.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "core/ops.hpp"

namespace qmaps {

struct Axis {
  std::string coordinate;
  double lo = 0, hi = 1;
  std::int64_t bins = 1;

  std::vector<double> edges() const;
};

// One or two axes.
class Histogram {
 public:
  Histogram() = default;
  Histogram(std::string name, std::vector<Axis> axes);

  // One sample: a value per axis.
  void add(const double* x) { add_lanes<double>(x, true); }

  // One sample per alive lane of V: the values of axis k in x[k]. The fractional bins are computed
  // in V, with the same arithmetic for double, so every path bins alike; counting is per lane.
  template <class V>
  void add_lanes(const V* x, ops::mask_t<V> alive) {
    V f[2] = {V(0.0), V(0.0)};  // a 1D histogram's second bin stays 0
    // no lane, every lane (comparing masks themselves is unsafe: sse2 compares their NaN bits)
    ops::mask_t<V> below = V(0.0) != V(0.0), inside = V(0.0) == V(0.0);
    for (int k = 0; k < rank_; ++k) {
      f[k] = (x[k] - V(lo_[k])) * V(scale_[k]);
      below = below | (x[k] < V(lo_[k]));
      inside = inside & (x[k] < V(hi_[k]));
    }
    const auto live = ops::lanes_of(alive), low = ops::lanes_of(below), in = ops::lanes_of(inside);
    const auto fx = ops::lanes_of(f[0]);
    const auto fy = ops::lanes_of(f[1]);
    for (std::size_t l = 0; l < live.size(); ++l) {
      if (!live[l]) continue;
      ++samples_;
      if (low[l] || !in[l]) {
        ++(low[l] ? underflow_ : overflow_);
        continue;
      }
      const std::int64_t i = std::min(static_cast<std::int64_t>(fx[l]), bins_[0] - 1);
      const std::int64_t j = std::min(static_cast<std::int64_t>(fy[l]), bins_[1] - 1);
      ++counts_[static_cast<std::size_t>(i * bins_[1] + j)];
    }
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
  int rank_ = 1;
  double lo_[2] = {0, 0}, hi_[2] = {1, 1}, scale_[2] = {1, 1};
  std::int64_t bins_[2] = {1, 1};
  std::vector<std::int64_t> counts_;
  std::int64_t underflow_ = 0, overflow_ = 0, samples_ = 0;
};

}  // namespace qmaps
