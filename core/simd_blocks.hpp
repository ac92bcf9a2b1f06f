#pragma once
// A SIMD path's entry point (declared in core/dispatch.hpp): orbits [first, first + count) in
// blocks of lanes × chains, the number of chains chosen at run time. Included only by the per-ISA
// translation units (core/simd_unit.cpp.in).
#include <cstddef>

#include "core/block.hpp"
#include "core/dispatch.hpp"

namespace qmaps {

template <class Map, class Arch>
void advance_blocks(const typename Map::Coeffs& c, Ensemble& e, std::size_t first,
                    std::size_t count, int chains, const RunPlan& plan, Observers* observers) {
  using V = xsimd::batch<double, Arch>;
  const std::size_t block = V::size * static_cast<std::size_t>(chains);
  // A map may allow fewer chains (Map::max_chains): the others are not compiled for it.
  constexpr int most = [] {
    if constexpr (requires { Map::max_chains; }) return Map::max_chains;
    return 8;
  }();
  const auto blocks = [&]<int K>() {
    if constexpr (K <= most)
      for (std::size_t o = first; o < first + count; o += block)
        advance_block<Map, V, K>(c, e, o, plan, observers, Stepping::chunks);
  };
  switch (chains) {
    case 1: blocks.template operator()<1>(); break;
    case 2: blocks.template operator()<2>(); break;
    case 4: blocks.template operator()<4>(); break;
    case 8: blocks.template operator()<8>(); break;
  }
}

}  // namespace qmaps
