// The cost of observing: Suris on every SIMD ISA the CPU has, 2^18 orbits, 1000 steps per
// iteration (bench_size), default chains: raw; with the invariants tracked and a 128×128 (q1, q2) density sampled every
// `stride` steps; a section alone (q1 = 0 both ways, iterate, cap 50); and the default preset's
// observers (invariants and density every 10 steps, the section q1 = 0 upward with cap 2), and
// that section alone.
// items_per_second = particle-steps/s; histogram_updates_per_second counts density samples.
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "core/isa.hpp"
#include "bench_ensemble.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

Section q1_section(int direction, std::int64_t cap, std::size_t orbits, long long steps) {
  Section s;
  s.name = "q1";
  s.plane = Coordinate::q1;
  s.direction = direction;
  s.x = Coordinate::q2;
  s.y = Coordinate::p2;
  s.cap = cap;
  s.density = Histogram("q1", {{"q2", -1, 1, 128}, {"p2", -1, 1, 128}});
  s.points = std::make_shared<SectionPoints>(orbits, Section::slots_per_orbit(cap, direction, steps));
  return s;
}

void observe(benchmark::State& state, Isa isa, bool invariants, bool density, int section) {
  const long long stride = state.range(0);
  const int threads = static_cast<int>(state.range(1));
  const auto model = make_model("suris", {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}});
  const auto orbits = static_cast<std::size_t>(bench_size().simd_orbits);
  const long long steps = bench_size().steps;
  Ensemble e = bench_ensemble(*model, orbits);
  // Each iteration observes afresh, as each segment of a run does (its sections' caps anew).
  const auto make = [&] {
    Observers o;
    if (section == 2) o.sections.push_back(q1_section(0, 50, orbits, steps));  // alone, both ways
    if (section == 1) o.sections.push_back(q1_section(1, 2, orbits, steps));   // the preset's
    if (density)
      o.densities.push_back({Histogram("q1q2", {{"q1", -1, 1, 128}, {"q2", -1, 1, 128}}),
                             {Coordinate::q1, Coordinate::q2}});
    return o;
  };
  std::int64_t samples = 0;
  for (auto _ : state) {
    Observers o = make();
    model->advance(e, next_steps(e, steps, invariants, stride), Execution{isa, threads},
                   o.empty() ? nullptr : &o);
    if (density) samples += o.densities[0].histogram.samples();
  }
  describe(state, "suris", isa_name(isa), static_cast<double>(orbits),
           static_cast<double>(steps), threads);
  state.counters["stride"] = static_cast<double>(stride);
  if (density)
    state.counters["histogram_updates_per_second"] = benchmark::Counter(
        static_cast<double>(samples), benchmark::Counter::kIsRate);
}

// Each kind of observing on each ISA: observe/<kind>/<isa>/stride:S/threads:T.
const bool registered = [] {
  struct Kind {
    const char* name;
    bool invariants, density;
    int section;
    std::vector<long> strides;
  };
  const Kind kinds[] = {{"raw", false, false, 0, {1000}},
                        {"invariants", true, false, 0, {1, 10, 100}},
                        {"invariants_density", true, true, 0, {1, 10, 100}},
                        {"density", false, true, 0, {1, 10, 100}},
                        {"section", false, false, 2, {1000}},
                        {"preset_section", false, false, 1, {1000}},
                        {"preset", true, true, 1, {10}}};
  for (Isa isa : runnable_isas())
    for (const Kind& k : kinds) {
      auto* b = benchmark::RegisterBenchmark(
                    ("observe/" + std::string(k.name) + "/" + std::string(isa_name(isa))).c_str(),
                    observe, isa, k.invariants, k.density, k.section)
                    ->ArgNames({"stride", "threads"})
                    ->Unit(benchmark::kMillisecond)
                    ->UseRealTime();
      for (long stride : k.strides)
        for (long threads : {1, 2}) b->Args({stride, threads});
    }
  return true;
}();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
