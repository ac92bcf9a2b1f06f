#pragma once
// A SIMD path's entry points (declared in core/dispatch.hpp): orbits [first, first + count)
// advanced in blocks of lanes × chains, the number of chains chosen at run time; and their
// invariants, lanes at a time. Included only by the per-ISA translation units
// (core/simd_unit.cpp.in).
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>

#include "core/block.hpp"
#include "core/dispatch.hpp"

namespace qmaps {

template <class Map, class Arch>
void advance_blocks(const typename Map::Coeffs& c, Ensemble& e, std::size_t first,
                    std::size_t count, int chains, const RunPlan& plan, Observers* observers) {
  using V = xsimd::batch<double, Arch>;
  const std::size_t block = V::size * static_cast<std::size_t>(chains);
  // Only the counts of ChainRange<Map> are compiled (ModelOf::within clamps a run's into them).
  using Chains = ChainRange<Map>;
  const auto blocks = [&]<int K>() {
    if constexpr (K >= Chains::least && K <= Chains::most)
      for (std::size_t o = first; o < first + count; o += block)
        advance_block<Map, V, K, Stepping::chunks>(c, e, o, plan, observers);
    else
      throw std::logic_error("advance_blocks: " + std::to_string(K) + " chains are not compiled");
  };
  switch (chains) {
    case 1: blocks.template operator()<1>(); break;
    case 2: blocks.template operator()<2>(); break;
    case 4: blocks.template operator()<4>(); break;
    case 8: blocks.template operator()<8>(); break;
    default: throw std::logic_error("advance_blocks: chains must be 1, 2, 4 or 8");
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
