// A map written as formulas against the same map built in: Suris (ensembles/presets/
// suris-formulas.toml, the built-in kernel's operations exactly) on each SIMD ISA, 1 and 2
// threads, raw and with its chaos record of one deviation (lambda, FLI, MEGNO).
// items_per_second = particle-steps/s; compare a formula row with its built-in row of one run:
//   build/bench/formulas_bench --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
#include <benchmark/benchmark.h>

#include <optional>
#include <string>

#include "bench_maps.hpp"
#include "core/isa.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

const std::string formulas_preset = QMAPS_SOURCE_DIR "/ensembles/presets/suris-formulas.toml";

// written: the formulas' map; deviations 0 or 1.
void step(benchmark::State& state, bool written, int deviations, Isa isa) {
  const auto orbits = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const long long steps = bench_size().steps;
  const std::string key = std::string(written ? "formulas" : "built-in") + "/" +
                          std::to_string(deviations) + "/" + std::string(isa_name(isa));
  auto& setup = bench_setup(key, orbits, [&] {
    const std::optional<ChaosOptions> chaos =
        deviations ? std::optional(ChaosOptions{false, 10}) : std::nullopt;
    if (written) return map_of(Config::load(formulas_preset), chaos);
    return chaos ? make_model("suris", suris_params, *chaos) : make_model("suris", suris_params);
  });
  Ensemble& e = *setup.ensemble;
  for (auto _ : state) {
    setup.model->advance(e, next_steps(e, steps, false), Execution{isa, threads});
    benchmark::DoNotOptimize(e.state[2][0]);
  }
  describe(state, written ? "suris-formulas" : "suris",
           std::string(isa_name(isa)) + (deviations ? "+lyapunov" : ""),
           static_cast<double>(orbits), static_cast<double>(steps), threads);
}

const bool registered = [] {
  for (Isa isa : runnable_isas()) {
    if (isa == Isa::sse2) continue;  // an exactly rounded fma per lane: a correctness path
    for (int deviations : {0, 1})
      for (bool written : {false, true})
        benchmark::RegisterBenchmark((std::string(written ? "formulas" : "built_in") + "/" +
                                      std::string(isa_name(isa)) + (deviations ? "/lyapunov" : ""))
                                         .c_str(),
                                     step, written, deviations, isa)
            ->ArgNames({"orbits", "threads"})
            ->Args({bench_size().simd_orbits / 4, 1})
            ->Args({bench_size().simd_orbits / 4, 2})
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
  }
  return true;
}();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
