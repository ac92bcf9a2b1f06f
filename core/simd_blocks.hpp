#pragma once
// A SIMD path's entry points (declared in core/dispatch.hpp): orbits [first, first + count)
// advanced in blocks of lanes × chains, the number of chains chosen at run time; and their
// invariants, lanes at a time. Included only by the per-ISA translation units
// (core/simd_unit.cpp.in).
#include <cstddef>
#include <span>

#include "core/block.hpp"
#include "core/dispatch.hpp"

namespace qmaps {

template <class Map, class Arch>
void advance_blocks(const typename Map::Coeffs& c, Ensemble& e, std::size_t first,
                    std::size_t count, int chains, const RunPlan& plan, Observers* observers) {
  using V = xsimd::batch<double, Arch>;
  const std::size_t block = V::size * static_cast<std::size_t>(chains);
  // A map may allow fewer chains (Map::min_chains, Map::max_chains, applied by ModelOf::within):
  // the others are not compiled for it.
  constexpr int least = [] {
    if constexpr (requires { Map::min_chains; }) return Map::min_chains;
    return 1;
  }();
  constexpr int most = [] {
    if constexpr (requires { Map::max_chains; }) return Map::max_chains;
    return 8;
  }();
  const auto blocks = [&]<int K>() {
    if constexpr (K >= least && K <= most)
      for (std::size_t o = first; o < first + count; o += block)
        advance_block<Map, V, K, Stepping::chunks>(c, e, o, plan, observers);
  };
  switch (chains) {
    case 1: blocks.template operator()<1>(); break;
    case 2: blocks.template operator()<2>(); break;
    case 4: blocks.template operator()<4>(); break;
    case 8: blocks.template operator()<8>(); break;
  }
}

template <class Map, class Arch>
void invariants_of_orbits(const typename Map::Coeffs& c, const Ensemble& e, std::size_t first,
                          std::size_t count, std::span<double* const> out) {
  using V = xsimd::batch<double, Arch>;
  constexpr std::size_t W = V::size;
  // Whole lanes from the aligned orbit at or before `first`: the state is padded to whole blocks.
  for (std::size_t o = first / W * W; o < first + count; o += W) {
    V values[Map::max_invariants];
    Map::invariants(c, detail::Lanes<Map, V>::load(e, o), values);
    alignas(64) double lanes[W];
    for (std::size_t k = 0; k < out.size(); ++k) {
      values[k].store_aligned(lanes);
      for (std::size_t l = 0; l < W; ++l)
        if (o + l >= first && o + l < first + count) out[k][o + l - first] = lanes[l];
    }
  }
}

}  // namespace qmaps
