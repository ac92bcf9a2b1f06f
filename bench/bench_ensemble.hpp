#pragma once
// The ensemble every benchmark steps: orbits from the box [−0.5, 0.5]⁴ (seed 1), and a plan
// that runs on from wherever the last iteration stopped.
#include "core/model.hpp"
#include "ensembles/box.hpp"
#include "ensembles/initial_conditions.hpp"

namespace qmaps {

inline Ensemble bench_ensemble(const Model& model, std::size_t orbits) {
  const Box box({{{-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}}}, 1, orbits);
  return model.start(generate(box).points, Start::taylor, 1e8);
}

// The next `steps` steps of e, invariants tracked or not.
inline RunPlan next_steps(const Ensemble& e, long long steps, bool track_invariants,
                          long long stride = 1) {
  RunPlan plan;
  plan.total = 1LL << 60;
  plan.first = e.step;
  plan.last = e.step + steps;
  plan.stride = stride;
  plan.track_invariants = track_invariants;
  return plan;
}

}  // namespace qmaps
