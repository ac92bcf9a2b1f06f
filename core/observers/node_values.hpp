#pragma once
// The coordinates of a state's node in V, indexed by Coordinate: q always, p when asked (a
// reversed step), t when the map keeps a clock; 0 for the others.
#include <array>
#include <cstddef>

#include "core/observers/coordinate.hpp"
#include "core/ops.hpp"

namespace qmaps {

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

// One coordinate of the node: the same value node_values gives for it.
template <class Map, class V>
V node_value(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
             Coordinate coordinate) {
  const auto k = static_cast<std::size_t>(coordinate);
  if (coordinate == Coordinate::t) {
    if constexpr (Map::time_per_orbit) return Map::clock(s);
    return V(0.0);
  }
  if (is_momentum(coordinate)) return Map::phase(c, s)[k];
  return Map::position(c, s)[k];
}

}  // namespace qmaps
