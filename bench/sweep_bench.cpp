// The cost of a sweep (docs/sweeps.md): 64 points of the flow (order 6, with lambda, FLI and MEGNO)
// over (beta/alpha, delta/alpha) = {1, ..., 8} x {0, 2, ..., 14}, 64 orbits each, on the best ISA
// and 2 threads, stepped
//   - as one sweep (core/runner: OpenMP over the blocks of every point),
//   - point by point (each point's own run, one after the other),
//   - against one run of one point with as many orbits as the whole sweep.
// items_per_second = particle-steps/s; compare the rows within one run:
//   build/bench/sweep_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "bench_ensemble.hpp"
#include "core/isa.hpp"
#include "core/runner.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

constexpr std::size_t points = 64, orbits = 64;

std::unique_ptr<Model> flow(double beta_over_alpha, double delta_over_alpha) {
  return make_model("flow", {{"A", 0.5}, {"B", 2.0}, {"alpha", 0.5},
                             {"beta", 0.5 * beta_over_alpha}, {"delta", 0.5 * delta_over_alpha},
                             {"h", 0.02}, {"order", 6}},
                    ChaosOptions{});
}

struct Points {
  std::vector<std::unique_ptr<Model>> models;
  std::vector<Ensemble> ensembles;
};

Points& sweep_points() {
  static Points p = [] {
    Points out;
    for (std::size_t k = 0; k < points; ++k) {
      out.models.push_back(flow(static_cast<double>(1 + k / 8), 2.0 * static_cast<double>(k % 8)));
      out.ensembles.push_back(bench_ensemble(*out.models.back(), orbits));
    }
    return out;
  }();
  return p;
}

const Execution x{best_isa(), 2, 8};

void as_one_sweep(benchmark::State& state) {
  auto& p = sweep_points();
  std::vector<RunPart> parts;
  for (std::size_t k = 0; k < points; ++k) parts.push_back({p.models[k].get(), &p.ensembles[k], nullptr});
  const long long steps = bench_size().steps;
  for (auto _ : state) {
    advance_parts(parts, next_steps(p.ensembles[0], steps, true), x);
    benchmark::DoNotOptimize(p.ensembles[0].state[0][0]);
  }
  describe(state, "flow", std::string(isa_name(x.isa)) + "+lyapunov+sweep",
           static_cast<double>(points * orbits), static_cast<double>(steps), x.threads);
}

void point_by_point(benchmark::State& state) {
  auto& p = sweep_points();
  const long long steps = bench_size().steps;
  for (auto _ : state) {
    for (std::size_t k = 0; k < points; ++k)
      p.models[k]->advance(p.ensembles[k], next_steps(p.ensembles[k], steps, true), x);
    benchmark::DoNotOptimize(p.ensembles[0].state[0][0]);
  }
  describe(state, "flow", std::string(isa_name(x.isa)) + "+lyapunov+point_by_point",
           static_cast<double>(points * orbits), static_cast<double>(steps), x.threads);
}

void one_run(benchmark::State& state) {
  auto& setup = bench_setup("flow-one-point", points * orbits, [] { return flow(8, 6); });
  const long long steps = bench_size().steps;
  for (auto _ : state) {
    setup.model->advance(*setup.ensemble, next_steps(*setup.ensemble, steps, true), x);
    benchmark::DoNotOptimize(setup.ensemble->state[0][0]);
  }
  describe(state, "flow", std::string(isa_name(x.isa)) + "+lyapunov+one_run",
           static_cast<double>(points * orbits), static_cast<double>(steps), x.threads);
}

BENCHMARK(as_one_sweep)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(point_by_point)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(one_run)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
