#pragma once
// A Poincaré section: every step, an oriented crossing of the plane `coordinate = value` between
// consecutive iterates n and n + 1 of an orbit that has not escaped records (orbit, n + 1, x, y):
//   iterate  the iterate after the crossing (a point of the orbit; the mode for discrete maps);
//   linear   the linear interpolation to the plane (a map has no flow between iterates: an
//            interpolation, not a point of the orbit);
//   exact    for a map that integrates a flow (flow, leapfrog) and a position plane: the flow's
//            own point on the plane, integrated from the nearer iterate by Hénon's method
//            (the map's to_plane); a crossing it cannot integrate (p vanishing on the way) is
//            interpolated linearly and counted in `interpolated`.
// At most `cap` points per orbit are kept (section_points.hpp: each orbit's in its
// own slots, so in (orbit, step) order whatever the threads), while the section's density counts
// every crossing. Watched in registers by section_lanes.hpp.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "core/observers/coordinate.hpp"
#include "core/observers/histogram.hpp"
#include "core/observers/section/section_points.hpp"

namespace qmaps {

enum class SectionMode { iterate, linear, exact };
inline constexpr std::array<std::string_view, 3> section_mode_names = {"iterate", "linear", "exact"};

struct Section {
  std::string name;
  Coordinate plane = Coordinate::q1;
  double value = 0;
  int direction = 1;    // +1: from below to at-or-above; −1: from above to at-or-below; 0: both
  SectionMode mode = SectionMode::iterate;
  Coordinate x = Coordinate::q2, y = Coordinate::p2;
  std::int64_t cap = 0;
  Histogram density;  // over (x, y): every crossing
  // At most `cap` per orbit; shared by the thread partials (an orbit belongs to one thread).
  std::shared_ptr<SectionPoints> points;
  std::int64_t interpolated = 0;  // mode exact: the crossings interpolated linearly instead

  // Whether a crossing's point needs the state before it too (linear and exact).
  bool needs_before() const { return mode != SectionMode::iterate; }
  // The flow is integrated from the whole phase point.
  bool needs_momentum() const {
    return mode == SectionMode::exact || is_momentum(plane) || is_momentum(x) || is_momentum(y);
  }

  // The slots an orbit needs over `steps` steps: no more than the cap, nor than the crossings
  // the steps allow (one a step both ways; one in two steps one way, since each crossing
  // upward must come back down before the next).
  static std::int64_t slots_per_orbit(std::int64_t cap, int direction, long long steps);

  Section empty_copy() const;  // the density's counts 0; the points shared
  void merge(const Section& partial) {  // its counts
    density.merge(partial.density);
    interpolated += partial.interpolated;
  }
  void finish();  // flushes the density's pending tallies
};

}  // namespace qmaps
