#pragma once
// The one list of maps. Everything that must know every map derives from it: the catalogue behind
// --map and `qmaps list`, the per-ISA translation units (CMakeLists.txt counts the entries), the
// agreement, contraction, reversibility, drift and convergence tests, the benchmarks and
// `qmaps check`'s defaults. Adding a map: its header, one line here (the type, and its header in
// the comment, which its per-ISA units include alone), a preset and a section in docs/maps.md
// (tests/maps_test.cpp checks both). The last, Formula, is any map written as
// formulas (docs/formulas.md): its paths are compiled here, its definition comes at run time.
#include <tuple>

#include "kernels/case2.hpp"
#include "kernels/case2_hky.hpp"
#include "kernels/case3.hpp"
#include "kernels/flow.hpp"
#include "kernels/formula_map.hpp"
#include "kernels/suris.hpp"

namespace qmaps::kernels {

// clang-format off
using Maps = std::tuple<
    Suris,           // kernels/suris.hpp
    Case2,           // kernels/case2.hpp
    Case2Staggered,  // kernels/case2.hpp
    Case2Hky,        // kernels/case2_hky.hpp
    Case3,           // kernels/case3.hpp
    Flow,            // kernels/flow.hpp
    Leapfrog,        // kernels/flow.hpp
    Formula>;        // kernels/formula_map.hpp
// clang-format on

// f(Map{}) for every built-in map of the list, in its order.
template <class F>
void for_each_map(F&& f) {
  const auto built_in = [&](auto map) {
    if constexpr (!DefinedAtRunTime<decltype(map)>) f(map);
  };
  std::apply([&](auto... map) { (built_in(map), ...); }, Maps{});
}
inline constexpr std::size_t built_in_maps = std::tuple_size_v<Maps> - 1;

}  // namespace qmaps::kernels
