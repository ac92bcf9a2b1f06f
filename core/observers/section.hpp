#pragma once
// A Poincaré section: every step, an oriented crossing of the plane `coordinate = value` between
// consecutive iterates n and n + 1 of an orbit that has not escaped records (orbit, n + 1, x, y):
// mode `iterate` the iterate after the crossing (a point of the orbit), mode `linear` the linear
// interpolation to the plane (a map has no flow between iterates: an interpolation, not a point
// of the orbit). At most `cap` points per orbit are kept (section_points.hpp: each orbit's in its
// own slots, so in (orbit, step) order whatever the threads), while the section's density counts
// every crossing. Watched in registers by section_lanes.hpp.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "core/observers/coordinate.hpp"
#include "core/observers/histogram.hpp"
#include "core/observers/section_points.hpp"

namespace qmaps {

struct Section {
  std::string name;
  Coordinate plane = Coordinate::q1;
  double value = 0;
  int direction = 1;    // +1: from below to at-or-above; −1: from above to at-or-below; 0: both
  bool linear = false;  // mode: linear interpolation to the plane, else the iterate after it
  Coordinate x = Coordinate::q2, y = Coordinate::p2;
  std::int64_t cap = 0;
  Histogram density;  // over (x, y): every crossing
  // At most `cap` per orbit; shared by the thread partials (an orbit belongs to one thread).
  std::shared_ptr<SectionPoints> points;

  bool needs_momentum() const { return is_momentum(plane) || is_momentum(x) || is_momentum(y); }

  // The slots an orbit needs over `steps` steps: no more than the cap, nor than the crossings
  // the steps allow (one a step both ways; one in two steps one way, since each crossing
  // upward must come back down before the next).
  static std::int64_t slots_per_orbit(std::int64_t cap, int direction, long long steps);

  Section empty_copy() const;  // the density's counts 0; the points shared
  void merge(const Section& partial) { density.merge(partial.density); }  // its density counts
  void finish();  // flushes the density's pending tallies
};

}  // namespace qmaps
