#pragma once
// The runner: advances an ensemble from plan.first to plan.last on the path that `x` names. The
// scalar reference (core/block.hpp at width 1) takes one orbit at a time, one checked step at a
// time, no threads: every other path must reproduce it bit for bit. A SIMD path
// (core/dispatch.hpp) takes whole blocks of lanes × chains orbits, OpenMP-parallel with a static
// schedule; each thread counts into its own empty copy of the observers' histograms, merged
// exactly in thread order when all are done (integer counts), and writes its orbits' section
// points straight into their slots (core/observers/section_points.hpp).
#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <omp.h>

#include "core/dispatch.hpp"
#include "core/ensemble.hpp"
#include "core/error.hpp"
#include "core/execution.hpp"
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
      advance_block<Map, double, 1>(c, e, orbit, plan, observers, Stepping::single_steps);
  } else {
    simd_path<Map>(x.isa).advance(c, e, first, count, x.chains, plan, observers);
  }
}

template <class Map>
void run(const typename Map::Coeffs& c, Ensemble& e, const RunPlan& plan, const Execution& x,
         Observers* observers) {
  if (plan.stride < 1) throw usage_error("stride must be >= 1");
  if (x.isa == Isa::scalar) {
    advance_range<Map>(c, e, 0, e.orbits, plan, x, observers);
  } else {
    const std::size_t block = block_orbits(x);
    if (Ensemble::padding % block != 0)
      throw usage_error("chains must be 1, 2, 4 or 8 (got " + std::to_string(x.chains) + ")");
    // Whole blocks of real orbits; the padding lanes past the last real orbit are never sampled.
    const long long blocks = static_cast<long long>((e.orbits + block - 1) / block);
    std::vector<Observers> partials(static_cast<std::size_t>(x.threads));
#pragma omp parallel num_threads(x.threads)
    {
      auto& partial = partials[static_cast<std::size_t>(omp_get_thread_num())];
      if (observers) partial = observers->empty_copy();
      Observers* mine = observers ? &partial : nullptr;
#pragma omp for schedule(static)
      for (long long b = 0; b < blocks; ++b)
        advance_range<Map>(c, e, static_cast<std::size_t>(b) * block, block, plan, x, mine);
    }
    if (observers) observers->merge(std::move(partials));
  }
  if (observers) observers->finish();
  e.step = plan.last;
}

}  // namespace qmaps
