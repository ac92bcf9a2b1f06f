#pragma once
// Each map's SIMD paths, one per ISA compiled: the entry points that the ISA's own translation
// unit (core/simd_unit.cpp.in, the only code compiled with that ISA's flags) instantiates for
// every map of kernels/maps.hpp. Derived from the ISA list (core/isa_list.hpp).
#include <array>
#include <cstddef>
#include <span>
#include <string>

#include <xsimd/xsimd.hpp>

#include "core/ensemble.hpp"
#include "core/error.hpp"
#include "core/isa.hpp"
#include "core/observers/observers.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

// The xsimd architecture of each ISA of the list.
template <Isa isa>
struct arch_for;
#define QMAPS_ARCH_FOR(name, arch, ...) \
  template <>                           \
  struct arch_for<Isa::name> {          \
    using type = arch;                  \
  };
QMAPS_FOR_EACH_ISA(QMAPS_ARCH_FOR)
#undef QMAPS_ARCH_FOR
template <Isa isa>
using arch_of = typename arch_for<isa>::type;

// Advances orbits [first, first + count) in blocks of lanes × chains orbits; chains ∈ {1, 2, 4, 8};
// count is a multiple of the block. Samples go into `observers` (one per thread) when not null.
// Defined in core/block.hpp.
template <class Map, class Arch>
void advance_blocks(const typename Map::Coeffs& c, Ensemble& e, std::size_t first,
                    std::size_t count, int chains, const RunPlan& plan, Observers* observers);

// The invariants of orbits [first, first + count) into out[k][0, count), for each invariant k of
// the map: the values of Map::invariants at double, lanes at a time. Defined in
// core/simd_blocks.hpp.
template <class Map, class Arch>
void invariants_of_orbits(const typename Map::Coeffs& c, const Ensemble& e, std::size_t first,
                          std::size_t count, std::span<double* const> out);

// a·b + c written as two operations, in a batch and in a scalar, in the ISA's translation unit:
// both are 0 for the probe's inputs when contraction is off there (core/fp_probe.hpp).
template <class Map, class Arch>
std::array<double, 2> contraction_probe(double a, double b, double c);

template <class Map>
struct SimdPath {
  void (*advance)(const typename Map::Coeffs&, Ensemble&, std::size_t, std::size_t, int,
                  const RunPlan&, Observers*);
  void (*invariants)(const typename Map::Coeffs&, const Ensemble&, std::size_t, std::size_t,
                     std::span<double* const>);
  std::array<double, 2> (*contraction_probe)(double, double, double);
};

// The path of `Map` for `isa`; an ISA this build did not compile is an `unsupported` error.
// Defined for every map of the list, plain and with its deviations, in one generated unit
// (core/simd_paths.cpp.in), the only one besides core/isa.cpp that knows which ISAs were compiled:
// so the others compile the same whichever were, and a build for one ISA shares them (ccache)
// with a build for all.
template <class Map>
SimdPath<Map> simd_path(Isa isa);

}  // namespace qmaps
