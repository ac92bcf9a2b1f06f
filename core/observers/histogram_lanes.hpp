#pragma once
// Histogram::add_lanes, for V = double and every batch: the runner's paths include this; the
// rest of the program sees only core/observers/histogram.hpp, free of SIMD headers.
#include <cstdint>

#include "core/observers/histogram.hpp"
#include "core/ops.hpp"

namespace qmaps {

template <class V, class Mask>
void Histogram::add_lanes(const V* x, Mask alive) {
  const auto slots = ops::integer_lanes(rank_ == 2 ? slot<2>(x) : slot<1>(x));
  if (pending_samples_ > pending_limit - slots.size()) flush();
  if (ops::all(alive)) {
    pending_samples_ += slots.size();
    for (const std::uint64_t s : slots) ++pending_[s];
    return;
  }
  const auto lanes = ops::lanes_of(alive);
  for (std::size_t l = 0; l < slots.size(); ++l)
    if (lanes[l]) {
      ++pending_samples_;
      ++pending_[slots[l]];
    }
}

template <int rank, class V>
V Histogram::slot(const V* x) const {
  ops::mask_t<V> below = x[0] < V(lo_[0]), inside = x[0] < V(hi_[0]);
  // row-major: i0 · bins1 + i1, exact in doubles; rounding may give f = bins, hence the min
  V cell = ops::min(ops::floor((x[0] - V(lo_[0])) * V(scale_[0])), V(last_[0]));
  if constexpr (rank == 2) {
    below = below | (x[1] < V(lo_[1]));
    inside = inside & (x[1] < V(hi_[1]));
    const V f = ops::floor((x[1] - V(lo_[1])) * V(scale_[1]));
    cell = cell * V(bins1_) + ops::min(f, V(last_[1]));
  }
  const V tally = ops::select(below, V(tallies_[0]), V(tallies_[1]));
  return ops::select(inside & ops::negate(below), cell, tally);
}

}  // namespace qmaps
