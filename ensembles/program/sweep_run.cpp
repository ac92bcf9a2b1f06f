#include "ensembles/program/sweep_run.hpp"

#include <unistd.h>

#include <cstdio>
#include <optional>
#include <ostream>
#include <vector>

#include "core/error.hpp"
#include "ensembles/io/h5.hpp"
#include "core/memory_limit.hpp"
#include "core/runner.hpp"
#include "core/thread_limit.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/io/output_lock.hpp"
#include "ensembles/io/sweep_output.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/progress.hpp"
#include "ensembles/program/run_setup.hpp"
#include "ensembles/program/segments.hpp"

namespace qmaps {
namespace {

// Refuses, before any point but the first has its observers, a sweep whose points cannot all
// fit in memory: each point's run is the first's (the same keys and map) with its own orbits.
void check_memory(const Config& config, const Run& first,
                  const std::vector<InitialConditions>& starts) {
  double bytes = (first.x.threads - 1) * bytes_per_thread();  // the threads serve every point
  std::size_t orbits = 0;
  for (const auto& s : starts) {
    bytes += memory_of(first, s.orbits());
    orbits += s.orbits();
  }
  check_fits(bytes, config.where("sweep[0]"),
             std::to_string(starts.size()) + " points, " + std::to_string(orbits) +
                 " orbits in all, with their observers,");
}

}  // namespace

int run_sweep(const Config& config, const Sweep& sweep, const RunOptions& options,
              const std::string& started, const InterruptGuard& interrupt, std::ostream& log) {
  const std::size_t points = sweep.points();
  // First every point's map and initial conditions (which fix its orbits), then the first
  // point's run, from which the whole sweep's memory is known before the others are made.
  std::vector<std::unique_ptr<Model>> models;
  std::vector<InitialConditions> starts;
  std::optional<Config> first_point;  // kept: the keys its readers used, for reject_unknown()
  for (std::size_t k = 0; k < points; ++k) {
    Config point = sweep.config_of(config, k);
    try {  // the point's own map and, for a shell, its own energy surface
      models.push_back(map_of(point, chaos_options_of(point)));
      starts.push_back(options.points ? InitialConditions::of_points(point, options.points)
                                      : InitialConditions::from_config(point, *models.back(),
                                                                         stop_on_signal));
    } catch (const Error& e) {
      throw Error(e.code(), "[[sweep]] " + sweep.label(k) + ": " + e.what());
    }
    if (k == 0) first_point = std::move(point);
  }
  std::vector<Run> runs;
  for (std::size_t k = 0; k < points; ++k) {
    Config point = k == 0 ? std::move(*first_point) : sweep.config_of(config, k);
    Run r = run_of(point, std::move(models[k]), starts[k].orbits(), options);
    if (r.checkpoint_every > 0)
      throw usage_error(point.where("run", "checkpoint_every") +
                        ": a sweep keeps no checkpoint (it runs to the end or stops with nothing "
                        "written)");
    r.kind = starts[k].kind();
    r.rejects_points = starts[k].generator().rejects_points();
    r.description = starts[k].description();
    r.seed = starts[k].seed();
    r.command_line = options.command_line;
    r.started = started;
    if (k == 0) point.reject_unknown();
    if (k == 0) check_memory(config, r, starts);
    runs.push_back(std::move(r));
  }
  const Run& first = runs.front();

  const OutputLock lock(first.path);  // first: a second run to this output is refused
  h5::AtomicFile output(first.path);
  auto file = output.create_hdf5(first.deflate);
  const auto groups = create_sweep_runs(file.root(), points);
  std::vector<Ensemble> ensembles;
  std::uint64_t rejected = 0;
  std::size_t orbits = 0;
  for (std::size_t k = 0; k < points; ++k) {
    Run& r = runs[k];
    ensembles.push_back(r.model->ensemble(r.orbits, r.measured));
    Ensemble& e = ensembles.back();
    const auto initial =
        r.per_orbit ? std::optional(groups[k].create_group("initial")) : std::nullopt;
    if (initial) create_phase(*initial, r.orbits);
    r.rejected = starts[k].start(
        *r.model, e, r.start, r.plan.escape_bound,
        [&](std::size_t from, std::span<const Phase> at) {
          if (initial) write_phase_part(*initial, from, at);
        },
        orbits_per_part);
    for (auto& t : r.trajectories) record(t, *r.model, e, r.plan);
    rejected += r.rejected;
    orbits += r.orbits;
  }

  // All points step together in segments (ensembles/program/segments.hpp).
  const RunPlan plan = first.plan;
  const Execution x = first.x;
  Progress progress(!options.quiet && isatty(STDERR_FILENO), log, orbits, 0, plan.total);
  std::vector<Observers> blanks;
  for (const auto& r : runs) blanks.push_back(r.observers.empty_copy());
  const SegmentLoop segments{plan, SegmentLoop::sweep_aim, 0, progress, interrupt,
                             options.on_segment};
  const int signal = segments.run(
      0,
      [&](const RunPlan& segment) {
        std::vector<Observers> parts;
        std::vector<RunPart> work;
        for (std::size_t k = 0; k < points; ++k) parts.push_back(blanks[k].empty_copy());
        for (std::size_t k = 0; k < points; ++k)
          work.push_back({runs[k].model.get(), &ensembles[k],
                          runs[k].observers.empty() ? nullptr : &parts[k]});
        advance_parts(work, segment, x);
        for (std::size_t k = 0; k < points; ++k)
          if (!runs[k].observers.empty()) runs[k].observers.merge(std::move(parts[k]));
      },
      [](long long) {});
  if (signal != 0) {
    progress.end();
    log << "qmaps: " << signal_name(signal) << " at step " << ensembles.front().step << " of "
        << plan.total << ": a sweep keeps no checkpoint; stopped, nothing was written\n";
    return static_cast<int>(ExitCode::interrupted);
  }
  progress.end();
  const double seconds = progress.seconds();

  const std::string finished = utc_now();
  std::vector<RunRecord> records;
  for (std::size_t k = 0; k < points; ++k) {
    runs[k].observers.finish();
    records.push_back(record_of(runs[k], ensembles[k], 0, started, finished, options.command_line));
  }
  naming_failures(first.path, [&] {
    write_sweep(file.root(), sweep, records);
    file.close();
  });
  output.commit();

  std::size_t escaped = 0;
  for (const auto& e : ensembles) escaped += e.escaped();
  const double rate = static_cast<double>(orbits) * static_cast<double>(plan.total) /
                      (seconds > 0 ? seconds : 1e-300);
  char line[512];
  std::snprintf(line, sizeof line,
                "qmaps: %s, sweep of %zu points, %zu orbits x %lld steps in %.3f s (%.3g "
                "particle-steps/s, %s, %d thread%s), %zu escaped%s -> %s\n",
                std::string(first.model->name()).c_str(), points, orbits, plan.total, seconds,
                rate, std::string(isa_name(x.isa)).c_str(), x.threads, x.threads == 1 ? "" : "s",
                escaped,
                first.rejects_points ? (", " + std::to_string(rejected) + " rejected").c_str() : "",
                first.path.c_str());
  log << line;
  return 0;
}

}  // namespace qmaps
