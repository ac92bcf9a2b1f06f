#pragma once
// The runner: advances an ensemble from plan.first to plan.last on the path that `x` names. The
// scalar reference (core/block.hpp at width 1) takes one orbit at a time. A SIMD path
// (core/dispatch.hpp) takes whole blocks of lanes × chains orbits, OpenMP-parallel with a static
// schedule; each thread counts into its own empty copy of the observers' histograms, merged
// exactly in thread order when all are done (integer counts), and writes its orbits' section
// points straight into their slots (core/observers/section_points.hpp).
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

template <class Map>
void run(const typename Map::Coeffs& c, Ensemble& e, const RunPlan& plan, const Execution& x,
         Observers* observers) {
  if (plan.stride < 1) throw usage_error("stride must be >= 1");
  if (x.isa == Isa::scalar) {
    advance_reference<Map>(c, e, plan, observers);
  } else {
    const auto advance = simd_path<Map>(x.isa).advance;
    const std::size_t block = isa_lanes(x.isa) * static_cast<std::size_t>(x.chains);
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
        advance(c, e, static_cast<std::size_t>(b) * block, block, x.chains, plan, mine);
    }
    if (observers) observers->merge(std::move(partials));
  }
  if (observers) observers->finish();
  e.step = plan.last;
}

}  // namespace qmaps
