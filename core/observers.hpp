#pragma once
// What a run measures while it advances: density histograms of phase-space coordinates, sampled
// at step 0 and wherever the invariants are (multiples of `stride`, and the last step), for the
// orbits that have not escaped. Each thread fills its own empty_copy(); merge() adds them exactly.
#include <string>
#include <string_view>
#include <vector>

#include "core/histogram.hpp"

namespace qmaps {

// The coordinates a histogram can be over: q1, q2, p1, p2 at node n, and t for a map whose
// physical time differs per orbit.
enum class Coordinate { q1 = 0, q2 = 1, p1 = 2, p2 = 3, t = 4 };
Coordinate parse_coordinate(std::string_view name, bool time_per_orbit);  // throws usage_error

struct Density {
  Histogram histogram;
  std::vector<Coordinate> coordinates;  // one per axis
};

struct Observers {
  std::vector<Density> densities;

  bool empty() const { return densities.empty(); }
  bool needs_momentum() const;  // any axis over p1 or p2 (a reversed step per sample)
  Observers empty_copy() const;
  void merge(const Observers& partial);
};

}  // namespace qmaps
