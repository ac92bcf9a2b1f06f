// The integrability tests' costs (docs/integrability.md):
//   field_orbits/<map>/<p>/<orbits>/<threads>  orbits over F_p, each to its return (the period
//       statistics), or, with max_period 64, 10^6 orbits stepped 64 times each (stepping alone);
//       items_per_second = map steps/s over all orbits
//   degrees/<map>  the degree test of `qmaps integrability` at its defaults (2 primes × 2 lines, 30
//       steps or the degree cap); items_per_second = F_p(t) steps/s
//   heights/<map>  40 steps over Q (or to 2^20 bits)
//   build/bench/integrability_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <omp.h>

#include <map>
#include <memory>
#include <string>

#include "ensembles/program/commands.hpp"
#include "integrability/degree_growth.hpp"
#include "integrability/finite_field_orbits.hpp"
#include "integrability/height_growth.hpp"
#include "integrability/verdict.hpp"

namespace qmaps {
namespace {

const exact::ExactMap& the_map(const std::string& name) {
  static std::map<std::string, exact::ExactMap> made;
  if (!made.contains(name)) {
    ParamValues p = {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}};
    if (name == "leapfrog") p.merge(ParamValues{{"beta", 0.5}, {"delta", 0.4}});
    const bool built_in = name == "suris" || name == "leapfrog";
    if (!built_in) p.clear();
    const std::string file = built_in ? name
                             : name.starts_with("henon")
                                 ? QMAPS_SOURCE_DIR "/tests/fixtures/maps/" + name + ".toml"
                                 : QMAPS_SOURCE_DIR "/ensembles/presets/" + name + ".toml";
    made.emplace(name, exact_map_named(file, p));
  }
  return made.at(name);
}

void field_orbits(benchmark::State& state, const std::string& name, std::uint64_t max_period) {
  const auto p = static_cast<std::uint64_t>(state.range(0));
  const auto orbits = static_cast<std::size_t>(state.range(1));
  const int threads = static_cast<int>(state.range(2));
  const exact::ExactMap& m = the_map(name);
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  double steps = 0;
  for (auto _ : state) {
    const auto f = exact::finite_field_orbits(m, p, orbits, max_period ? max_period : 1ULL << 40, 1);
    steps += f.steps;
    benchmark::DoNotOptimize(f.periods.data());
  }
  omp_set_num_threads(before);
  state.SetItemsProcessed(static_cast<std::int64_t>(steps));
}

void degrees(benchmark::State& state, const std::string& name) {
  const exact::ExactMap& m = the_map(name);
  double steps = 0;
  for (auto _ : state) {
    const auto o = exact::resolved({}, m);
    const auto t = exact::degree_test(m, o.degree_primes, o.lines, o.steps, o.degree_cap, 1);
    for (const auto& r : t.runs) steps += static_cast<double>(r.degrees.size() - 1);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(steps));
}

void heights(benchmark::State& state, const std::string& name) {
  const exact::ExactMap& m = the_map(name);
  double steps = 0;
  for (auto _ : state) {
    const auto t = exact::height_test(m, 40, 1 << 20, 1);
    steps += static_cast<double>(t.log_heights.size() - 1);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(steps));
}

void register_all() {
  for (const char* name : {"henon-quadratic", "mcmillan"})
    for (const int threads : {1, 2}) {
      benchmark::RegisterBenchmark(("field_orbits/" + std::string(name)).c_str(),
                                   [=](benchmark::State& s) { field_orbits(s, name, 0); })
          ->Args({10007, 1 << 12, threads})->Unit(benchmark::kMillisecond)->UseRealTime();
      benchmark::RegisterBenchmark(("field_stepping/" + std::string(name)).c_str(),
                                   [=](benchmark::State& s) { field_orbits(s, name, 64); })
          ->Args({10007, 1000000, threads})->Unit(benchmark::kMillisecond)->UseRealTime();
    }
  for (const char* name : {"suris", "suris-formulas", "leapfrog"})
    for (const int threads : {1, 2})
      benchmark::RegisterBenchmark(("field_stepping/" + std::string(name)).c_str(),
                                   [=](benchmark::State& s) { field_orbits(s, name, 64); })
          ->Args({101, 1000000, threads})->Unit(benchmark::kMillisecond)->UseRealTime();
  for (const char* name : {"suris", "suris-formulas", "suris-kicked", "mcmillan"}) {
    benchmark::RegisterBenchmark(("degrees/" + std::string(name)).c_str(),
                                 [=](benchmark::State& s) { degrees(s, name); })
        ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
    benchmark::RegisterBenchmark(("heights/" + std::string(name)).c_str(),
                                 [=](benchmark::State& s) { heights(s, name); })
        ->Unit(benchmark::kMillisecond)->UseRealTime();
  }
}

}  // namespace
}  // namespace qmaps

int main(int argc, char** argv) {
  qmaps::register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
