// The cost of the tunes (docs/tunes.md): Suris' map (its example parameters), 2^18
// orbits of the box [−0.5, 0.5]⁴ on 2 threads and 8 chains, on each SIMD ISA here: 2 × 2048 steps
// stepped raw, then the same steps with both windows' tunes (NAFF of q1 and q2) and the diffusion.
// items_per_second = orbit-steps/s; the ratio of a path's two rows is the tunes' price:
//   build/bench/tunes_bench --benchmark_repetitions=15 --benchmark_enable_random_interleaving=true
//       --benchmark_report_aggregates_only=true   (the rows interleaved: the noise falls on each alike)
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "bench_maps.hpp"
#include "core/isa.hpp"
#include "core/observers/tunes/tunes.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

constexpr long long window = 2048;

// The ensemble of `orbits` with the tunes' columns, started once per process.
Ensemble& tune_ensemble(const Model& model, std::size_t orbits) {
  static std::unique_ptr<Ensemble> e;
  if (!e || e->orbits != orbits) {
    e.reset();
    const Box box({{{-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}}}, 1, orbits);
    e = std::make_unique<Ensemble>(
        model.ensemble(orbits, std::vector<std::string>{std::string(TuneColumns::key)}));
    model.start_at(*e, 0, generate(box).points, Start::taylor, 1e8);
    e->fill_padding();
  }
  return *e;
}

void tunes(benchmark::State& state, Isa isa, bool with_tunes) {
  const auto orbits = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  static const auto model = make_model("suris", suris_params);
  Ensemble& e = tune_ensemble(*model, orbits);
  RunPlan plan;  // both windows from step 0 of whatever state the last iteration left
  plan.total = plan.last = 2 * window;
  plan.stride = plan.total;  // the invariants sampled once, at the end
  plan.measure_orbits = with_tunes;
  if (with_tunes) plan.tunes = {window, 2};
  for (auto _ : state) {
    model->advance(e, plan, Execution{isa, threads, 8});
    benchmark::DoNotOptimize(e.columns.back()[0]);
  }
  describe(state, "suris", std::string(isa_name(isa)) + (with_tunes ? "+tunes" : "+raw"),
           static_cast<double>(orbits), static_cast<double>(2 * window), threads);
}

const bool registered = [] {
  for (const Isa isa : runnable_isas())
    for (const bool with_tunes : {false, true})
      benchmark::RegisterBenchmark(
          ("suris/" + std::string(isa_name(isa)) + (with_tunes ? "/tunes" : "/raw")).c_str(), tunes,
          isa, with_tunes)
          ->ArgNames({"orbits", "threads"})
          ->Args({bench_size().simd_orbits, 2})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
  return true;
}();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
