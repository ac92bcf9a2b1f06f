#pragma once
// The tunes of every orbit (core/observers/tunes/tunes.hpp, docs/tunes.md) and its class by
// diffusion: 0 regular, 1 chaotic (diffusion above the threshold), 2 escaped within the windows,
// 3 bounded without a tune (both signals 0); /tunes in a run's file, a sweep's per-point summary.
#include <cstdint>
#include <span>
#include <vector>

#include "core/aligned_array.hpp"
#include "core/ensemble.hpp"
#include "ensembles/io/run_observers/orbit_classes.hpp"

namespace qmaps {

struct TuneTable : OrbitClasses {
  // nu1, nu2, nu1_second, nu2_second, diffusion (empty: the run has no tunes)
  std::span<const AlignedArray<double>> columns;
  std::vector<std::uint8_t> classes;
  std::int64_t no_tune = 0;
  std::int64_t round_off = 0;  // orbits whose diffusion is the floor: tunes equal to round-off
  // Column c's finite values, orbit by orbit.
  std::vector<double> finite(std::size_t c) const;
};
TuneTable tune_table(const Ensemble& e, double diffusion_threshold);

}  // namespace qmaps
