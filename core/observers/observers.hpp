#pragma once
// What a run measures while it advances, for the orbits that have not escaped:
//  - densities: histograms of phase-space coordinates, sampled at step 0 and wherever the
//    invariants are (multiples of `stride`, and the last step);
//  - Poincaré sections: every step, an oriented crossing of the plane `coordinate = value`
//    between consecutive iterates n and n + 1 records (orbit, n + 1, x, y): mode `iterate` the
//    iterate after the crossing (a point of the orbit), mode `linear` the linear interpolation to
//    the plane (a map has no flow between iterates: an interpolation, not a point of the orbit);
//    at most `cap` points per orbit, while the section's density histogram counts every crossing.
// Each thread fills its own empty_copy(), each block's points put in (orbit, step) order as it
// ends; merge() adds counts and appends the partials' points as ordered runs, and finish() merges
// the runs: the result does not depend on threads, and no sort is needed.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/observers/histogram.hpp"
#include "core/observers/large_pages.hpp"

namespace qmaps {

// The coordinates of node n: q1, q2, p1, p2, and t for a map whose time differs per orbit.
enum class Coordinate { q1 = 0, q2 = 1, p1 = 2, p2 = 3, t = 4 };
Coordinate parse_coordinate(std::string_view name, bool time_per_orbit);  // throws usage_error
std::string_view coordinate_name(Coordinate c);
inline bool is_momentum(Coordinate c) { return c == Coordinate::p1 || c == Coordinate::p2; }

struct Density {
  Histogram histogram;
  std::vector<Coordinate> coordinates;  // one per axis
};

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
  Histogram density;                   // over (x, y): every crossing
  std::vector<SectionPoint, LargePages<SectionPoint>> points;  // at most `cap` per orbit
  std::shared_ptr<std::vector<std::int64_t>> kept;  // points kept per orbit (shared by threads;
                                                    // an orbit belongs to one thread)
  std::vector<std::size_t> runs;  // where each ordered run of points after the first begins

  // Keeps the point (x, y) of a crossing of `orbit` at `step` if the orbit's cap allows.
  void keep(std::int64_t orbit, std::int64_t step, double x, double y) {
    auto& count = (*kept)[static_cast<std::size_t>(orbit)];
    if (count < cap) {
      ++count;
      points.push_back({orbit, step, x, y});
    }
  }
  // Puts points [from, end), each orbit's in step order (a block's), in (orbit, step) order.
  void order_by_orbit(std::size_t from);
};

struct Observers {
  std::vector<Density> densities;
  std::vector<Section> sections;

  bool empty() const { return densities.empty() && sections.empty(); }
  bool densities_need_momentum() const;  // any axis over p1 or p2 (a reversed step per sample)
  bool sections_need_momentum() const;
  Observers empty_copy() const;
  void merge(Observers&& partial);  // takes the partial's points, in (orbit, step) order
  void merge(std::vector<Observers>&& partials);  // the same, one after the other
  void finish();  // flushes the histograms' pending tallies, merges the ordered runs of points
};

}  // namespace qmaps
