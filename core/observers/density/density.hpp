#pragma once
// A density: a histogram of phase-space coordinates over the orbits that have not escaped,
// sampled at step 0 and wherever the invariants are (multiples of `stride`, and the last step).
// Partials merge by adding counts, exact in any order. Sampled in registers by density_lanes.hpp.
#include <vector>

#include "core/observers/coordinate.hpp"
#include "core/observers/histogram.hpp"

namespace qmaps {

struct Density {
  Histogram histogram;
  std::vector<Coordinate> coordinates;  // one per axis

  bool needs_momentum() const {  // an axis over p1 or p2: a reversed step per sample
    for (Coordinate c : coordinates)
      if (is_momentum(c)) return true;
    return false;
  }
  Density empty_copy() const { return {histogram.empty_copy(), coordinates}; }
  void merge(const Density& partial) { histogram.merge(partial.histogram); }
  void finish() { histogram.flush(); }
};

}  // namespace qmaps
