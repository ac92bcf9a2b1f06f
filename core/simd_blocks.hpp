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
  for (std::size_t o = first; o < first + count; o += block) switch (chains) {
      case 1: advance_block<Map, V, 1>(c, e, o, plan, observers, Stepping::chunks); break;
      case 2: advance_block<Map, V, 2>(c, e, o, plan, observers, Stepping::chunks); break;
      case 4: advance_block<Map, V, 4>(c, e, o, plan, observers, Stepping::chunks); break;
      case 8: advance_block<Map, V, 8>(c, e, o, plan, observers, Stepping::chunks); break;
    }
}

}  // namespace qmaps
