// Stepping throughput of each map on each path: items_per_second = particle-steps/s.
// Raw stepping (no invariant tracking), 1000 steps per iteration, 2^18 and 2^22 orbits.
//   build/bench/kernels_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <string>

#include "core/isa.hpp"
#include "ensembles/box.hpp"
#include "ensembles/catalogue.hpp"

namespace qmaps {
namespace {

constexpr long long steps = 1000;

void step_ensemble(benchmark::State& state, std::string map, Isa isa) {
  const auto orbits = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const auto model = make_model(map, {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}});
  Box box;
  box.orbits = orbits;
  box.seed = 1;
  box.ranges = {{{-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}}};
  Ensemble e = model->start(box.points(), Start::taylor, 1e8);
  RunPlan plan;
  plan.total = 1LL << 60;
  plan.track_invariants = false;
  for (auto _ : state) {
    plan.first = e.step;
    plan.last = e.step + steps;
    model->advance(e, plan, Execution{isa, threads, 4});
    benchmark::DoNotOptimize(e.state[2][0]);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long long>(orbits) * steps);
  state.SetLabel(std::string(isa_name(isa)));
}

const bool registered = [] {
  for (const char* map : {"suris"}) {
    auto* scalar = benchmark::RegisterBenchmark((std::string(map) + "/scalar").c_str(),
                                                step_ensemble, map, Isa::scalar);
    scalar->ArgNames({"orbits", "threads"})->Args({1 << 18, 1});
    scalar->Unit(benchmark::kMillisecond)->UseRealTime();
    for (Isa isa : runnable_isas()) {
      auto* b = benchmark::RegisterBenchmark(
          (std::string(map) + "/" + std::string(isa_name(isa))).c_str(), step_ensemble, map, isa);
      b->ArgNames({"orbits", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
      // The exactly rounded per-lane FMA of sse2 is slow: its large case would take minutes.
      for (long orbits : {1L << 18, 1L << 22})
        for (long threads : {1, 2})
          if (isa != Isa::sse2 || orbits == 1L << 18) b->Args({orbits, threads});
    }
  }
  return true;
}();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
