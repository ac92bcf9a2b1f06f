#pragma once
// Histogram::add_lanes, for V = double and every batch: the runner's paths include this; the
// rest of the program sees only core/observers/histogram.hpp, free of SIMD headers.
#include <bit>
#include <cstdint>

#include "core/observers/histogram.hpp"
#include "core/ops.hpp"

namespace qmaps {

template <class V>
auto Histogram::slots(const V* x) const {
  return ops::integer_lanes(rank_ == 2 ? slot<2>(x) : slot<1>(x));
}

template <class V, class Mask>
void Histogram::add_lanes(const V* x, Mask alive) {
  const auto lane_slots = slots(x);
  if (ops::all(alive)) {
    if (pending_samples_ > pending_limit - lane_slots.size()) flush();
    pending_samples_ += lane_slots.size();
    for (const std::uint64_t s : lane_slots) ++pending_[s];
    return;
  }
  for (std::uint64_t lanes = ops::bits(alive); lanes != 0; lanes &= lanes - 1)
    add_slot(lane_slots[static_cast<std::size_t>(std::countr_zero(lanes))]);
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
