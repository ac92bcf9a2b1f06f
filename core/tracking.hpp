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


// Adds the coordinates of the alive lanes to every density histogram.
template <class Map, class V>
void sample_densities(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                      ops::mask_t<V> alive, Observers& o) {
  constexpr std::size_t W = ops::lanes<V>;
  std::array<std::array<double, W>, 5> x{};
  if (o.needs_momentum()) {
    const auto phase = Map::phase(c, s);
    for (std::size_t k = 0; k < 4; ++k) x[k] = ops::lanes_of(phase[k]);
  } else {
    const auto q = Map::position(c, s);
    x[0] = ops::lanes_of(q[0]);
    x[1] = ops::lanes_of(q[1]);
  }
  if constexpr (requires { Map::clock(s); }) x[4] = ops::lanes_of(Map::clock(s));
  const auto live = ops::lanes_of(alive);
  for (std::size_t l = 0; l < W; ++l) {
    if (!live[l]) continue;
    for (auto& d : o.densities) {
      double v[2];
      for (std::size_t a = 0; a < d.coordinates.size(); ++a)
        v[a] = x[static_cast<std::size_t>(d.coordinates[a])][l];
      d.histogram.add(v);
    }
  }
}

}  // namespace qmaps
