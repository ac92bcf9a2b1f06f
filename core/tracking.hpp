#pragma once
// What both paths do to an orbit besides the map's arithmetic, written once for V = double and
// V = batch: step it and report a solver's fault, sample its invariants (max |I_n − I_0| over
// the alive lanes).
#include <array>
#include <cstddef>
#include <type_traits>
#include <utility>

#include "core/ensemble.hpp"
#include "core/observers.hpp"
#include "core/ops.hpp"

namespace qmaps {

// Whether the map's step solves an equation and reports faults (see core/map_concept.hpp).
template <class Map>
inline constexpr bool reports_faults = !std::is_void_v<decltype(Map::step(
    std::declval<const typename Map::Coeffs&>(),
    std::declval<typename Map::template State<double>&>()))>;

// One step in place; returns the lanes' fault codes (0: none; always 0 for explicit maps).
template <class Map, class V>
V step_reporting_faults(const typename Map::Coeffs& c, typename Map::template State<V>& s) {
  if constexpr (reports_faults<Map>) {
    return Map::step(c, s);
  } else {
    Map::step(c, s);
    return V(0.0);
  }
}

template <class Map, class V>
void sample_invariants(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                       Ensemble& e, std::size_t orbit, ops::mask_t<V> alive) {
  V values[Map::max_invariants];
  Map::invariants(c, s, values);
  for (std::size_t k = 0; k < e.invariant_max_drift.size(); ++k) {
    const V initial = ops::load<V>(&e.invariant_initial[k][orbit]);
    double* drift_at = &e.invariant_max_drift[k][orbit];
    const V drift = ops::load<V>(drift_at);
    ops::store(drift_at, ops::select(alive, ops::max(drift, ops::abs(values[k] - initial)), drift));
  }
}


// The lanes' coordinates at the state's node, [coordinate][lane]: q always, p when asked (a
// reversed step), t when the map keeps a clock.
template <class V>
using NodeCoordinates = std::array<std::array<double, ops::lanes<V>>, 5>;

template <class Map, class V>
NodeCoordinates<V> node_coordinates(const typename Map::Coeffs& c,
                                    const typename Map::template State<V>& s, bool momentum) {
  NodeCoordinates<V> x{};
  if (momentum) {
    const auto phase = Map::phase(c, s);
    for (std::size_t k = 0; k < 4; ++k) x[k] = ops::lanes_of(phase[k]);
  } else {
    const auto q = Map::position(c, s);
    x[0] = ops::lanes_of(q[0]);
    x[1] = ops::lanes_of(q[1]);
  }
  if constexpr (requires { Map::clock(s); }) x[4] = ops::lanes_of(Map::clock(s));
  return x;
}

// Adds the coordinates of the alive lanes to every density histogram.
template <class Map, class V>
void sample_densities(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                      ops::mask_t<V> alive, Observers& o) {
  if (o.densities.empty()) return;
  const auto x = node_coordinates<Map>(c, s, o.densities_need_momentum());
  const auto live = ops::lanes_of(alive);
  for (std::size_t l = 0; l < live.size(); ++l) {
    if (!live[l]) continue;
    for (auto& d : o.densities) {
      double v[2];
      for (std::size_t a = 0; a < d.coordinates.size(); ++a)
        v[a] = x[static_cast<std::size_t>(d.coordinates[a])][l];
      d.histogram.add(v);
    }
  }
}

// Every section crossed by an alive lane between node n (`before`) and node n + 1 = `step`
// (the state s) is recorded; `before` becomes node n + 1.
template <class Map, class V>
void check_sections(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                    ops::mask_t<V> alive, Observers& o, std::size_t first_orbit, long long step,
                    NodeCoordinates<V>& before) {
  if (o.sections.empty()) return;
  const auto after = node_coordinates<Map>(c, s, o.sections_need_momentum());
  const auto live = ops::lanes_of(alive);
  for (std::size_t l = 0; l < live.size(); ++l) {
    if (!live[l]) continue;
    for (auto& section : o.sections) {
      const auto p = static_cast<std::size_t>(section.plane);
      if (!section.crosses(before[p][l], after[p][l])) continue;
      double b[5], a[5];
      for (std::size_t k = 0; k < 5; ++k) {
        b[k] = before[k][l];
        a[k] = after[k][l];
      }
      section.record(static_cast<std::int64_t>(first_orbit + l), step, b, a);
    }
  }
  before = after;
}

}  // namespace qmaps
