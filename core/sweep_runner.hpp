#pragma once
// The runner of several ensembles at once (a parameter sweep, docs/sweeps.md). Each ensemble is
// advanced from plan.first to plan.last by its own model (its map, its coefficients): OpenMP over
// the blocks of all of them with a dynamic schedule, so that many small ensembles keep every thread
// busy. Each thread counts into its own empty copy of each ensemble's observers, merged exactly
// when all are done. Every ensemble and its observers end as that model's advance() leaves them,
// byte for byte, whatever the threads and the schedule.
#include <span>

#include "core/ensemble.hpp"
#include "core/execution.hpp"
#include "core/model.hpp"
#include "core/observers/observers.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

struct SweepPart {
  const Model* model;
  Ensemble* ensemble;
  Observers* observers;  // null: none
};

void advance_sweep(std::span<const SweepPart> parts, const RunPlan& plan, const Execution& x);

}  // namespace qmaps
