#pragma once
// The one list of maps. Everything that must know every map derives from it: the catalogue behind
// --map and `qmaps list`, the per-ISA translation units (CMakeLists.txt counts the entries), the
// agreement, contraction, reversibility, drift and convergence tests, the benchmarks and
// `qmaps check`'s defaults. Adding a map: its header, one line here, a preset and a section in
// docs/maps.md (tests/maps_test.cpp checks both).
#include <tuple>

#include "kernels/case2.hpp"
#include "kernels/case2_hky.hpp"
#include "kernels/case3.hpp"
#include "kernels/flow.hpp"
#include "kernels/suris.hpp"

namespace qmaps::kernels {

// clang-format off
using Maps = std::tuple<
    Suris,
    Case2,
    Case2Staggered,
    Case2Hky,
    Case3,
    Flow,
    Leapfrog>;
// clang-format on

// f(Map{}) for every map of the list, in its order.
template <class F>
void for_each_map(F&& f) {
  std::apply([&](auto... map) { (f(map), ...); }, Maps{});
}

}  // namespace qmaps::kernels
