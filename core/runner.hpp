#pragma once
// The runner: advances an ensemble from plan.first to plan.last on the path that `x` names. The
// scalar reference (core/reference.hpp) takes one orbit at a time. A SIMD path (core/dispatch.hpp)
// takes whole blocks of lanes × chains orbits, OpenMP-parallel with a static schedule; each thread
// samples into its own empty copy of the observers, merged exactly when the thread is done
// (integer counts; section points are put in (orbit, step) order when the observers finish).
#include <cstddef>
#include <string>
#include <utility>

#include "core/dispatch.hpp"
#include "core/ensemble.hpp"
#include "core/error.hpp"
#include "core/execution.hpp"
#include "core/observers/observers.hpp"
#include "core/reference.hpp"
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
#pragma omp parallel num_threads(x.threads)
    {
      Observers partial = observers ? observers->empty_copy() : Observers{};
      Observers* mine = observers ? &partial : nullptr;
#pragma omp for schedule(static)
      for (long long b = 0; b < blocks; ++b)
        advance(c, e, static_cast<std::size_t>(b) * block, block, x.chains, plan, mine);
#pragma omp critical(qmaps_merge_observers)
      if (observers) observers->merge(std::move(partial));
    }
  }
  if (observers) observers->finish();
  e.step = plan.last;
}

}  // namespace qmaps
