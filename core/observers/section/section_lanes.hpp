#pragma once
// A section's watch over a block's lanes (or one orbit, V = double): the crossing test, and the
// recording of the lanes that crossed, the point computed in V and the density counted through
// the 16-bit tallies.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/map_concept.hpp"
#include "core/observers/histogram_lanes.hpp"
#include "core/observers/node_values.hpp"
#include "core/observers/section/section.hpp"

namespace qmaps {

// The lanes whose plane coordinate crosses `value` in `direction` (Section::direction) from a
// (node n) to b (node n + 1).
template <class V>
ops::mask_t<V> crosses(V value, int direction, V a, V b) {
  const auto up = (a < value) & (b >= value), down = (a > value) & (b <= value);
  return direction > 0 ? up : direction < 0 ? down : up | down;
}
template <class V>
ops::mask_t<V> crosses(const Section& section, V a, V b) {
  return crosses(V(section.value), section.direction, a, b);
}

// The point a crossing from node n (`before`) to node n + 1 (`after`) gives in the section's
// (x, y), with the lanes whose exact point had to be interpolated:
//   iterate  node n + 1's;
//   linear   the interpolation to the plane at f = (value − a)/(b − a) of the plane coordinate's
//            a → b (f = 1 where b = a);
//   exact    the map's flow from the nearer node whose momentum heads to the plane (forward from
//            n, backward from n + 1), else from the other; where neither heads there, or the flow
//            meets p_k = 0 on the way, the linear interpolation.
template <class Map, class V>
std::array<V, 2> section_point(const typename Map::Coeffs& c, const Section& section,
                               const std::array<V, 5>& before, const std::array<V, 5>& after,
                               ops::mask_t<V>& interpolated) {
  const auto x = static_cast<std::size_t>(section.x), y = static_cast<std::size_t>(section.y);
  const auto p = static_cast<std::size_t>(section.plane);
  interpolated = V(0.0) != V(0.0);
  if (section.mode == SectionMode::iterate) return {after[x], after[y]};
  const V a = before[p], b = after[p], value(section.value);
  const V f = ops::select(b == a, V(1.0), (value - a) / (b - a));
  const std::array<V, 2> linear = {before[x] + f * (after[x] - before[x]),
                                   before[y] + f * (after[y] - before[y])};
  if (section.mode == SectionMode::linear) return linear;
  if constexpr (FlowsToPlane<Map>) {
    const V to_before = value - a, to_after = value - b;  // ds from either node
    using Mask = ops::mask_t<V>;
    const Mask before_heads = to_before * before[2 + p] > V(0.0);
    const Mask after_heads = (to_after * after[2 + p] < V(0.0)) | (to_after == V(0.0));
    const Mask from_before =
        before_heads & (ops::negate(after_heads) | (ops::abs(to_before) <= ops::abs(to_after)));
    std::array<V, 4> start;
    for (std::size_t i = 0; i < 4; ++i) start[i] = ops::select(from_before, before[i], after[i]);
    const auto point = Map::to_plane(c, start, p, ops::select(from_before, to_before, to_after));
    Mask exact = before_heads | after_heads;
    for (const V& v : point) exact = exact & (v - v == V(0.0));  // finite
    interpolated = ops::negate(exact);
    return {ops::select(exact, point[x], linear[0]), ops::select(exact, point[y], linear[1])};
  } else {
    interpolated = V(0.0) == V(0.0);  // refused by the configuration: no flow to integrate
    return linear;
  }
}

// A crossing by the lanes of a batch, ready to record: each lane's point and its slot in the
// section's density, computed in V, and the lanes that crossed as bits (a few, usually one).
template <class V>
struct CrossingLanes {
  std::array<std::uint64_t, ops::lanes<V>> slots;
  std::array<double, ops::lanes<V>> x, y;
  std::uint64_t lanes;
};

// The crossing by the lanes of `crossing` from node n (`before`) to node n + 1 (`after`); the
// lanes whose point had to be interpolated are counted in the section.
template <class Map, class V>
CrossingLanes<V> crossing_lanes(const typename Map::Coeffs& c, Section& section,
                                ops::mask_t<V> crossing, const std::array<V, 5>& before,
                                const std::array<V, 5>& after) {
  ops::mask_t<V> interpolated;
  const auto xy = section_point<Map>(c, section, before, after, interpolated);
  section.interpolated += std::popcount(ops::bits(interpolated & crossing));
  return {section.density.slots(xy.data()), ops::lanes_of(xy[0]), ops::lanes_of(xy[1]),
          ops::bits(crossing)};
}

// Records a crossing, lane l's by orbit orbit_of(l) at step step_of(l): every crossing in the
// section's density; its point while the orbit's cap allows.
template <class V, class OrbitOf, class StepOf>
void keep_lanes(Section& section, const CrossingLanes<V>& x, OrbitOf orbit_of, StepOf step_of) {
  for (std::uint64_t lanes = x.lanes; lanes != 0; lanes &= lanes - 1) {
    const auto l = static_cast<std::size_t>(std::countr_zero(lanes));
    section.density.add_slot(x.slots[l]);
    if (section.cap > 0) section.points->keep(orbit_of(l), step_of(l), x.x[l], x.y[l]);
  }
}
// The same for lanes of one batch at one step: lane l's orbit is first_orbit + l.
template <class V>
void keep_lanes(Section& section, const CrossingLanes<V>& x, std::size_t first_orbit,
                long long step) {
  keep_lanes(section, x, [&](std::size_t l) { return first_orbit + l; },
             [&](std::size_t) { return step; });
}

// Every section crossed by an alive lane between node n (`before`) and node n + 1 = `step`
// (the state s) is recorded; `before` becomes node n + 1. Lanes are unpacked only on a crossing.
// `momentum`: whether any section reads p.
template <class Map, class V>
void check_sections(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                    ops::mask_t<V> alive, std::vector<Section>& sections, bool momentum,
                    std::size_t first_orbit, long long step, std::array<V, 5>& before) {
  if (sections.empty()) return;
  const auto after = node_values<Map>(c, s, momentum);
  for (auto& section : sections) {
    const auto p = static_cast<std::size_t>(section.plane);
    const auto crossing = crosses(section, before[p], after[p]) & alive;
    if (ops::any(crossing))
      keep_lanes(section, crossing_lanes<Map>(c, section, crossing, before, after), first_orbit,
                 step);
  }
  before = after;
}

}  // namespace qmaps
