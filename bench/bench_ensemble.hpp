#pragma once
// What every benchmark shares: the ensemble it steps (orbits from the box [−0.5, 0.5]⁴, seed 1,
// kept from one run of a benchmark to the next), a plan that runs on from wherever the last
// iteration stopped, the sizes (QMAPS_BENCH_SIZE = full, quick or tiny) and the description each
// result carries for bench/report: label "map/path", counters orbits, steps and threads.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "core/model.hpp"
#include "ensembles/kinds/box.hpp"
#include "ensembles/kinds/initial_conditions.hpp"

namespace qmaps {

// How much work one iteration does. full: the published figures; quick: a short look; tiny: a
// smoke test that every benchmark runs.
struct BenchSize {
  std::string_view name;
  long simd_orbits;      // orbits on the SIMD paths
  long million_orbits;   // a million-orbit ensemble (2^20), as users run: Suris on the best ISA
  long slow_orbits;      // orbits on the scalar path and sse2 (a per-lane exactly rounded FMA)
  long long steps;       // steps per iteration of the explicit maps
  long long slow_steps;  // steps per iteration of case3 (Newton) and flow (15 forces per step)
  int min_log2_orbits, max_log2_orbits;  // the runner's orbit sweep
  long long sweep_steps;                 // and its steps per iteration
};

inline const BenchSize& bench_size() {
  static const BenchSize sizes[] = {
      {"full", 1 << 18, 1 << 20, 1 << 12, 1000, 100, 10, 24, 64},
      {"quick", 1 << 16, 1 << 20, 1 << 10, 250, 25, 10, 20, 32},
      {"tiny", 1 << 8, 1 << 10, 1 << 8, 4, 2, 8, 10, 4},
  };
  const char* env = std::getenv("QMAPS_BENCH_SIZE");
  const std::string_view wanted = env && *env ? env : "full";
  for (const BenchSize& s : sizes)
    if (s.name == wanted) return s;
  throw usage_error("QMAPS_BENCH_SIZE must be full, quick or tiny (got '" + std::string(wanted) +
                    "')");
}

inline Ensemble bench_ensemble(const Model& model, std::size_t orbits) {
  const Box box({{{-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}}}, 1, orbits);
  return model.start(generate(box).points, Start::taylor, 1e8);
}

// The model and ensemble of the last benchmark that asked, built anew only when the map, its
// parameters or the number of orbits change: Google Benchmark calls a benchmark several times
// (iteration count, repetitions), and starting 2^24 orbits takes seconds.
struct BenchSetup {
  std::unique_ptr<Model> model;
  std::unique_ptr<Ensemble> ensemble;
};
inline BenchSetup& bench_setup(std::string_view key, std::size_t orbits,
                               const std::function<std::unique_ptr<Model>()>& make) {
  static BenchSetup setup;
  static std::string last_key;
  const std::string k = std::string(key) + "/" + std::to_string(orbits);
  if (k != last_key || !setup.ensemble) {
    setup.ensemble.reset();  // free the last one first
    setup.model = make();
    setup.ensemble = std::make_unique<Ensemble>(bench_ensemble(*setup.model, orbits));
    last_key = k;
  }
  return setup;
}

// The next `steps` steps of e, invariants tracked or not.
inline RunPlan next_steps(const Ensemble& e, long long steps, bool measure_orbits,
                          long long stride = 1) {
  RunPlan plan;
  plan.total = 1LL << 60;
  plan.first = e.step;
  plan.last = e.step + steps;
  plan.stride = stride;
  plan.measure_orbits = measure_orbits;
  return plan;
}

// items_per_second = particle-steps/s, and what bench/report needs to place the result.
inline void describe(benchmark::State& state, std::string_view map, std::string_view path,
                     double orbits, double steps, int threads) {
  state.SetItemsProcessed(static_cast<std::int64_t>(static_cast<double>(state.iterations()) *
                                                    orbits * steps));
  state.SetLabel(std::string(map) + "/" + std::string(path));
  state.counters["orbits"] = orbits;
  state.counters["steps"] = steps;
  state.counters["threads"] = threads;
}

}  // namespace qmaps
