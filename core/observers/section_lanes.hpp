#pragma once
// A section's watch over a block's lanes (or one orbit, V = double): the crossing test, and the
// recording of the lanes that crossed, the point computed in V and the density counted through
// the 16-bit tallies.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/observers/histogram_lanes.hpp"
#include "core/observers/node_values.hpp"
#include "core/observers/section.hpp"

namespace qmaps {

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
    if (lanes[l]) section.points->keep(first_orbit + l, step, x[l], y[l]);
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
    if (ops::any(crossing)) record_lanes(section, crossing, before, after, first_orbit, step);
  }
  before = after;
}

}  // namespace qmaps
