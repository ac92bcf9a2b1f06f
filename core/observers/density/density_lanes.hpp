#pragma once
// A density's sample of a block's lanes (or one orbit, V = double), while the block is in
// registers.
#include <cstddef>
#include <vector>

#include "core/observers/density/density.hpp"
#include "core/observers/histogram_lanes.hpp"
#include "core/observers/node_values.hpp"

namespace qmaps {

// Adds the coordinates of the alive lanes to every density; `momentum`: whether any density
// reads p (decided once per run rather than per sample).
template <class Map, class V>
void sample_densities(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                      ops::mask_t<V> alive, std::vector<Density>& densities, bool momentum) {
  if (densities.empty()) return;
  const auto x = node_values<Map>(c, s, momentum);
  for (auto& d : densities) {
    V v[2];
    for (std::size_t a = 0; a < d.coordinates.size(); ++a)
      v[a] = x[static_cast<std::size_t>(d.coordinates[a])];
    d.histogram.add_lanes(v, alive);
  }
}

}  // namespace qmaps
