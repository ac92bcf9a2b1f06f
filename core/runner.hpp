#pragma once
// The runner: advances ensembles from plan.first to plan.last on the path that `x` names. The
// scalar reference (core/block.hpp at width 1) takes one orbit at a time, one checked step at a
// time: every other path must reproduce it bit for bit. A SIMD path (core/dispatch.hpp) takes
// whole blocks of lanes × chains orbits. Each thread counts into its own empty copy of the
// observers' histograms, merged exactly when all are done (integer counts), and writes its
// orbits' section points straight into their slots (core/observers/section/section_points.hpp).
#include <algorithm>
#include <cstddef>
#include <span>

#include "core/dispatch.hpp"
#include "core/ensemble.hpp"
#include "core/execution.hpp"
#include "core/model.hpp"
#include "core/observers/observers.hpp"
#include "core/block.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

// Orbits in a block of path x: lanes × chains, or one on the scalar reference path.
inline std::size_t block_orbits(const Execution& x) {
  return x.isa == Isa::scalar ? 1 : isa_lanes(x.isa) * static_cast<std::size_t>(x.chains);
}

// Advances orbits [first, first + count) on this thread alone; count is a multiple of
// block_orbits(x) (a range may reach into the padding, whose lanes are never sampled).
template <class Map>
void advance_range(const typename Map::Coeffs& c, Ensemble& e, std::size_t first,
                   std::size_t count, const RunPlan& plan, const Execution& x,
                   Observers* observers) {
  if (x.isa == Isa::scalar) {
    for (std::size_t orbit = first; orbit < std::min(first + count, e.orbits); ++orbit)
      advance_block<Map, double, 1, Stepping::single_steps>(c, e, orbit, plan, observers);
  } else {
    simd_path<Map>(x.isa).advance(c, e, first, count, x.chains, plan, observers);
  }
}

// One part of a run: an ensemble advanced by its own model (its map, its coefficients), its samples
// into `observers` (null: none). A run is one part; a sweep (docs/sweeps.md) is one per point.
struct RunPart {
  const Model* model;
  Ensemble* ensemble;
  Observers* observers;
};

// Advances every part from plan.first to plan.last: OpenMP over the blocks of all of them (a
// static schedule for one part, a dynamic one for several, so that many small ensembles keep
// every thread busy). Each thread counts into its own empty copy of each part's observers, merged
// exactly in thread order when all are done; every part ends as the reference path leaves it,
// byte for byte, whatever the path, threads and schedule. The stride and the chains are checked
// here, once.
void advance_parts(std::span<const RunPart> parts, const RunPlan& plan, const Execution& x);

}  // namespace qmaps
