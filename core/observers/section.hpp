#pragma once
// A Poincaré section: every step, an oriented crossing of the plane `coordinate = value` between
// consecutive iterates n and n + 1 of an orbit that has not escaped records (orbit, n + 1, x, y):
// mode `iterate` the iterate after the crossing (a point of the orbit), mode `linear` the linear
// interpolation to the plane (a map has no flow between iterates: an interpolation, not a point
// of the orbit). At most `cap` points per orbit are kept, while the section's density counts
// every crossing. Watched in registers by section_lanes.hpp.
//
// Points come out of each block in (orbit, step) order (order_by_orbit); merge() appends the
// partials' points as ordered runs and finish() merges the runs, so that the points are in
// (orbit, step) order whatever the threads, with no sort.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/observers/coordinate.hpp"
#include "core/observers/histogram.hpp"
#include "core/observers/large_pages.hpp"

namespace qmaps {

struct SectionPoint {
  std::int64_t orbit, step;
  double x, y;
};

struct Section {
  std::string name;
  Coordinate plane = Coordinate::q1;
  double value = 0;
  int direction = 1;    // +1: from below to at-or-above; −1: from above to at-or-below; 0: both
  bool linear = false;  // mode: linear interpolation to the plane, else the iterate after it
  Coordinate x = Coordinate::q2, y = Coordinate::p2;
  std::int64_t cap = 0;
  Histogram density;                                          // over (x, y): every crossing
  std::vector<SectionPoint, LargePages<SectionPoint>> points;  // at most `cap` per orbit
  std::shared_ptr<std::vector<std::int64_t>> kept;  // points kept per orbit (shared by threads;
                                                    // an orbit belongs to one thread)
  std::vector<std::size_t> runs;  // where each ordered run of points after the first begins

  bool needs_momentum() const { return is_momentum(plane) || is_momentum(x) || is_momentum(y); }

  // Keeps the point (x, y) of a crossing of `orbit` at `step` if the orbit's cap allows.
  void keep(std::int64_t orbit, std::int64_t step, double x_value, double y_value) {
    auto& count = (*kept)[static_cast<std::size_t>(orbit)];
    if (count < cap) {
      ++count;
      points.push_back({orbit, step, x_value, y_value});
    }
  }
  // Puts points [from, end), each orbit's in step order (a block's), in (orbit, step) order.
  void order_by_orbit(std::size_t from);

  Section empty_copy() const;  // no points; the kept counts shared
  void merge(std::span<Section* const> partials);  // their counts, their points as ordered runs
  void finish();  // flushes the density's pending tallies, merges the runs of points
};

}  // namespace qmaps
