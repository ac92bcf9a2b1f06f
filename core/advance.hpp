#pragma once
// The SIMD path's entry point, declared for everyone and defined (core/block.hpp) only in the
// per-ISA translation units that instantiate it, each compiled with its ISA's flags.
#include <cstddef>

#include "core/ensemble.hpp"
#include "core/observers.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

// Advances orbits [first, first + count) in blocks of lanes × chains orbits; chains ∈ {1, 2, 4, 8};
// count is a multiple of the block. Samples go into `observers` (one per thread) when not null.
template <class Map, class Arch>
void advance_blocks(const typename Map::Coeffs& c, Ensemble& e, std::size_t first,
                    std::size_t count, int chains, const RunPlan& plan, Observers* observers);

}  // namespace qmaps
