// Writing a run's HDF5 file (docs/hdf5-schema.md): 10^6 orbits of Suris after 10 steps with their
// invariants tracked; each iteration writes the whole file (attributes, initial phase points by
// parts as the orbits start, final phase points, final state, invariants, drift histograms,
// escapes) under a temporary name and renames it, as `qmaps run` does. bytes_per_second is the
// file's size written per second; bytes_per_orbit the file's size over the orbits. gzip: 0 (the
// default, contiguous and uncompressed) or the level of [output] compression = "gzip".
//   build/bench/io_bench [--benchmark_repetitions=5 --benchmark_report_aggregates_only=true]
// The file goes to $TMPDIR (or /tmp) and is removed after each iteration, untimed.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <span>
#include <filesystem>
#include <string>

#include "bench_maps.hpp"
#include "ensembles/io/h5.hpp"
#include "core/isa.hpp"
#include "ensembles/kinds/box.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "kernels/catalogue.hpp"
#include "ensembles/io/output.hpp"

namespace qmaps {
namespace {

void write_file(benchmark::State& state) {
  const auto orbits = static_cast<std::size_t>(state.range(0));
  const int gzip = static_cast<int>(state.range(1));
  const auto model = make_model("suris", suris_params);
  const Box box({{{-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}, {-0.5, 0.5}}}, 1, orbits);
  const auto initial = generate(box).points;
  Ensemble e = model->start(initial, Start::taylor, 1e8);
  RunPlan plan;
  plan.total = plan.last = 10;
  const Execution x{best_isa(), 2, 4};
  model->advance(e, plan, x);

  const char* tmp = std::getenv("TMPDIR");
  const std::filesystem::path path = std::filesystem::path(tmp && *tmp ? tmp : "/tmp") /
                                     ("qmaps-io-bench-" + std::to_string(getpid()) + ".h5");
  std::uintmax_t bytes = 0;
  for (auto _ : state) {
    h5::AtomicFile output(path.string());
    auto file = output.create_hdf5(gzip);
    const auto initial_group = file.root().create_group("initial");
    create_phase(initial_group, orbits);
    for (std::size_t first = 0; first < orbits; first += orbits_per_part)  // by parts, as a run
      write_phase_part(initial_group, first,
                       std::span(initial).subspan(first, std::min(orbits_per_part, orbits - first)));
    RunRecord record{*model, e, plan, x, "box", box.seed(), Start::taylor};
    record.ensemble_description = box.description();
    write_run(file.root(), record);
    file.close();
    output.commit();
    bytes = std::filesystem::file_size(path);
    // Each iteration writes a new file, as a run does: the last one's removal (where the file
    // system discards its blocks, a wait on the disk) is not timed.
    state.PauseTiming();
    std::filesystem::remove(path);
    state.ResumeTiming();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes) * state.iterations());
  state.SetLabel("suris/hdf5");
  state.counters["orbits"] = static_cast<double>(orbits);
  state.counters["bytes_per_orbit"] = static_cast<double>(bytes) / static_cast<double>(orbits);
  state.counters["gzip"] = gzip;
}

const bool registered = [] {
  const long orbits = bench_size().name == "full" ? 1000000 : bench_size().simd_orbits;
  benchmark::RegisterBenchmark("io/write_run", write_file)
      ->ArgNames({"orbits", "gzip"})
      ->Args({orbits, 0})
      ->Args({orbits, 4})
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  return true;
}();

}  // namespace
}  // namespace qmaps

BENCHMARK_MAIN();
