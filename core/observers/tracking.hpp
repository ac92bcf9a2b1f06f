#pragma once
// What both paths do to an orbit besides the map's arithmetic, written once for V = double and
// V = batch: step it and report a solver's fault, track its invariants (max |I_n − I_0| over
// the alive samples), sample the densities and check the sections.
#include <array>
#include <cstddef>

#include "core/ensemble.hpp"
#include "core/observers/histogram_lanes.hpp"
#include "core/observers/observers.hpp"
#include "core/ops.hpp"

namespace qmaps {

// One step in place; returns the lanes' fault codes (0: none; always 0 for explicit maps).
template <class Map, class V>
V step_reporting_faults(const typename Map::Coeffs& c, typename Map::template State<V>& s) {
  if constexpr (Map::reports_faults) {
    return Map::step(c, s);
  } else {
    Map::step(c, s);
    return V(0.0);
  }
}

// One value's (a lane's or an orbit's) invariant tracking, held in registers while its block
// advances: the initial values and max |I_n − I_0| over the alive samples.
template <class Map, class V>
struct InvariantTrack {
  std::size_t count = 0;
  V initial[Map::max_invariants], drift[Map::max_invariants];

  void load(const Ensemble& e, std::size_t orbit) {
    count = e.invariant_max_drift.size();
    for (std::size_t k = 0; k < count; ++k) {
      initial[k] = ops::load<V>(&e.invariant_initial[k][orbit]);
      drift[k] = ops::load<V>(&e.invariant_max_drift[k][orbit]);
    }
  }
  void sample(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
              ops::mask_t<V> alive) {
    V values[Map::max_invariants];
    Map::invariants(c, s, values);
    for (std::size_t k = 0; k < count; ++k)
      drift[k] = ops::select(alive, ops::max(drift[k], ops::abs(values[k] - initial[k])), drift[k]);
  }
  void store(Ensemble& e, std::size_t orbit) const {
    for (std::size_t k = 0; k < count; ++k) ops::store(&e.invariant_max_drift[k][orbit], drift[k]);
  }
};

// The coordinates at the state's node, q1 q2 p1 p2 t: q always, p when asked (a reversed step),
// t when the map keeps a clock; 0 for the others.
template <class Map, class V>
std::array<V, 5> node_values(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                             bool momentum) {
  std::array<V, 5> x;
  x.fill(V(0.0));
  if (momentum) {
    const auto phase = Map::phase(c, s);
    for (std::size_t k = 0; k < 4; ++k) x[k] = phase[k];
  } else {
    const auto q = Map::position(c, s);
    x[0] = q[0];
    x[1] = q[1];
  }
  if constexpr (Map::time_per_orbit) x[4] = Map::clock(s);
  return x;
}

// Adds the coordinates of the alive lanes to every density histogram; `momentum`:
// o.densities_need_momentum(), decided once per run rather than per sample.
template <class Map, class V>
void sample_densities(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                      ops::mask_t<V> alive, Observers& o, bool momentum) {
  if (o.densities.empty()) return;
  const auto x = node_values<Map>(c, s, momentum);
  for (auto& d : o.densities) {
    V v[2];
    for (std::size_t a = 0; a < d.coordinates.size(); ++a)
      v[a] = x[static_cast<std::size_t>(d.coordinates[a])];
    d.histogram.add_lanes(v, alive);
  }
}

// The lanes whose plane coordinate crosses the section from a (node n) to b (node n + 1).
template <class V>
ops::mask_t<V> crosses(const Section& section, V a, V b) {
  const V v(section.value);
  const auto up = (a < v) & (b >= v), down = (a > v) & (b <= v);
  return section.direction > 0 ? up : section.direction < 0 ? down : up | down;
}

// The point a crossing from node n (`before`) to node n + 1 (`after`) gives in the section's
// (x, y): mode iterate, node n + 1's; mode linear, the interpolation to the plane at
// f = (value − a)/(b − a) of the plane coordinate's a → b (f = 1 where b = a).
template <class V>
std::array<V, 2> section_point(const Section& section, const std::array<V, 5>& before,
                               const std::array<V, 5>& after) {
  const auto x = static_cast<std::size_t>(section.x), y = static_cast<std::size_t>(section.y);
  std::array<V, 2> xy = {after[x], after[y]};
  if (section.linear) {
    const auto p = static_cast<std::size_t>(section.plane);
    const V a = before[p], b = after[p];
    const V f = ops::select(b == a, V(1.0), (V(section.value) - a) / (b - a));
    xy[0] = before[x] + f * (xy[0] - before[x]);
    xy[1] = before[y] + f * (xy[1] - before[y]);
  }
  return xy;
}

// Records the section's crossing at `step` by each lane of `crossing` (orbit first_orbit + lane):
// every crossing in the section's density, in V; its point while the orbit's cap allows.
template <class V>
void record_lanes(Section& section, ops::mask_t<V> crossing, const std::array<V, 5>& before,
                  const std::array<V, 5>& after, std::size_t first_orbit, long long step) {
  const auto xy = section_point(section, before, after);
  section.density.add_lanes(xy.data(), crossing);
  if (section.cap == 0) return;
  const auto lanes = ops::lanes_of(crossing);
  const auto x = ops::lanes_of(xy[0]), y = ops::lanes_of(xy[1]);
  for (std::size_t l = 0; l < lanes.size(); ++l)
    if (lanes[l]) section.keep(static_cast<std::int64_t>(first_orbit + l), step, x[l], y[l]);
}

// Every section crossed by an alive lane between node n (`before`) and node n + 1 = `step`
// (the state s) is recorded; `before` becomes node n + 1. Lanes are unpacked only on a crossing.
// `momentum`: o.sections_need_momentum().
template <class Map, class V>
void check_sections(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                    ops::mask_t<V> alive, Observers& o, bool momentum, std::size_t first_orbit,
                    long long step, std::array<V, 5>& before) {
  if (o.sections.empty()) return;
  const auto after = node_values<Map>(c, s, momentum);
  for (auto& section : o.sections) {
    const auto p = static_cast<std::size_t>(section.plane);
    const auto crossing = crosses(section, before[p], after[p]) & alive;
    if (ops::any(crossing)) record_lanes(section, crossing, before, after, first_orbit, step);
  }
  before = after;
}

}  // namespace qmaps
