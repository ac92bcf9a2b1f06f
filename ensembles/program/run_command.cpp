#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <ostream>

#include "core/error.hpp"
#include "core/io/h5.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/config/sweep_config.hpp"
#include "ensembles/io/checkpoint.hpp"
#include "ensembles/io/output.hpp"
#include "ensembles/io/output_lock.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/progress.hpp"
#include "ensembles/program/run_setup.hpp"
#include "ensembles/program/sweep_run.hpp"

namespace qmaps {
namespace {

// Advances the ensemble to the last step in segments (exact: a segmented run equals one call),
// writing a checkpoint every `checkpoint_every` steps and, on SIGINT, SIGTERM or SIGHUP, one
// before it stops; then writes the output file and removes the checkpoint.
int execute(Run& r, Ensemble& e, h5::AtomicFile& output, h5::File& file,
            const InterruptGuard& interrupt, const RunOptions& options, std::ostream& log) {
  const auto since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  const double starting = since(r.began);
  const std::string session_started = r.sessions.empty() ? r.started : utc_now();
  const long long first = e.step;
  const std::string checkpoint = r.path + checkpoint_suffix;
  const auto initial = r.per_orbit ? std::optional(file.root().open_group("initial")) : std::nullopt;
  const auto save = [&] {
    r.observers.finish();
    naming_failures(checkpoint, [&] {
      write_checkpoint(checkpoint,
                       record_of(r, e, first, session_started, utc_now(), options.command_line),
                       initial ? &*initial : nullptr);
    });
  };

  SelfSignal self_signal = SelfSignal::from_environment();
  Progress progress(!options.quiet && isatty(STDERR_FILENO), log, r.orbits, first, r.plan.total);
  // Each segment samples into empty observers, merged into the run's: the points so far are
  // neither copied nor sorted per segment, only before they are written (finish()).
  const Observers blank = r.observers.empty_copy();
  // Steps per segment: doubled or halved to take about 2 to 8 s (each segment is a pass over
  // the ensemble's memory; a signal waits for the segment's end).
  long long length = 1;
  do {
    RunPlan segment = r.plan;
    segment.first = e.step;
    segment.last = std::min(r.plan.total, e.step + length);
    if (r.checkpoint_every > 0)
      segment.last = std::min(segment.last, (e.step / r.checkpoint_every + 1) * r.checkpoint_every);
    segment.last = self_signal.segment_end(segment.first, segment.last);
    const double t = progress.seconds();
    Observers part = blank.empty_copy();
    r.model->advance(e, segment, r.x, r.observers.empty() ? nullptr : &part);
    r.observers.merge(std::move(part));
    const double took = progress.seconds() - t;
    progress.update(e.step);
    if (options.on_segment) options.on_segment(e.step, r.plan.total);
    if (e.step == r.plan.total) break;
    self_signal.deliver_if_due(e.step);
    if (interrupt.requested() && !options.checkpoint_on_interrupt) {
      progress.end();
      log << "qmaps: " << signal_name(interrupt.signal()) << " at step " << e.step << " of "
          << r.plan.total << ": stopped, nothing written\n";
      return static_cast<int>(ExitCode::interrupted);
    }
    if (interrupt.requested()) {
      save();
      progress.end();
      log << "qmaps: " << signal_name(interrupt.signal()) << " at step "
          << e.step << " of " << r.plan.total << ": checkpoint written to " << checkpoint
          << "; continue with: qmaps run --resume " << checkpoint << '\n';
      return static_cast<int>(ExitCode::interrupted);
    }
    if (r.checkpoint_every > 0 && e.step % r.checkpoint_every == 0) save();
    if (took < 2) length = std::min(2 * length, r.plan.total);
    else if (took > 8 && length > 1) length /= 2;
  } while (e.step < r.plan.total);
  progress.end();
  const double seconds = progress.seconds();

  const auto writing_began = std::chrono::steady_clock::now();
  r.observers.finish();
  naming_failures(r.path, [&] {  // an incomplete file is never committed
    write_run(file.root(),
              record_of(r, e, first, session_started, utc_now(), options.command_line));
    if (r.shard) write_kept(file.root(), r.observers);  // for qmaps merge
    file.close();
  });
  output.commit();
  std::remove(checkpoint.c_str());
  const double writing = since(writing_began);

  const double rate = static_cast<double>(r.orbits) * static_cast<double>(r.plan.total - first) /
                      (seconds > 0 ? seconds : 1e-300);
  char line[512];
  std::snprintf(line, sizeof line,
                "qmaps: %s, %zu orbits x %lld steps in %.3f s (%.3g particle-steps/s, %s, %d "
                "thread%s), %zu escaped%s -> %s\n",
                std::string(r.model->name()).c_str(), r.orbits, r.plan.total - first, seconds,
                rate, std::string(isa_name(r.x.isa)).c_str(), r.x.threads,
                r.x.threads == 1 ? "" : "s", e.escaped(),
                r.rejects_points ? (", " + std::to_string(r.rejected) + " rejected").c_str() : "",
                r.path.c_str());
  log << line;
  std::snprintf(line, sizeof line,
                "qmaps: time by phase: starting %.3f s, stepping and observing %.3f s, writing "
                "%.3f s\n",
                starting, seconds, writing);
  log << line;
  return 0;
}

int resume_command(const RunOptions& options, const InterruptGuard& interrupt,
                   std::ostream& log) {
  if (!options.config_path.empty() || !options.sets.empty() || !options.out.empty())
    throw usage_error(
        "--resume continues the run its checkpoint describes: give no config, --set or --out");
  const std::string& path = options.resume;
  const std::string suffix = checkpoint_suffix;
  if (path.size() <= suffix.size() || path.compare(path.size() - suffix.size(), suffix.size(), suffix) != 0)
    throw usage_error("--resume " + path + ": a checkpoint is named <output>" + suffix);

  const h5::File checkpoint = open_checkpoint(path);
  const auto root = checkpoint.root();
  try {
    const Config config = Config::parse(root.attr_string("config_resolved"), path + " (config_resolved)");
    // A shard's checkpoint resumes the shard: its range of the ensemble's orbits.
    RunOptions resumed = options;
    const bool shard = root.has_attr("shard");
    if (shard) resumed.shard = root.attr_string("shard");
    const auto orbits = root.attr_int64(shard ? "orbits_total" : "orbits");
    if (orbits <= 0) throw Error(ExitCode::io, "attribute orbits is " + std::to_string(orbits));
    Run r = run_of(config, map_of(config, chaos_options_of(config)),
                   static_cast<std::size_t>(orbits), resumed);
    if (static_cast<std::int64_t>(r.orbits) != root.attr_int64("orbits"))
      throw Error(ExitCode::io, "attribute orbits is " + std::to_string(root.attr_int64("orbits")) +
                                    "; shard " + r.shard->name() + " has " + std::to_string(r.orbits));
    r.path = path.substr(0, path.size() - suffix.size());
    read_provenance(root, r);
    r.rejected = static_cast<std::uint64_t>(root.attr_int64("rejected"));
    r.rejects_points = r.rejected > 0;  // the kind itself is not rebuilt on resumption
    r.sessions = root.attr_string("sessions");

    h5::AtomicFile output(r.path);
    auto file = output.create_hdf5(r.deflate);
    const OutputLock lock(r.path);
    Ensemble e = r.model->ensemble(r.orbits);
    read_ensemble(root, *r.model, e);
    if (e.step < 0 || e.step >= r.plan.total)
      throw Error(ExitCode::io, "its step " + std::to_string(e.step) + " is not in [0, " +
                                    std::to_string(r.plan.total) + ")");
    restore_observers(root, r.observers);
    read_trajectories(root, r.trajectories, r.plan.total);
    if (r.per_orbit) copy_phase(root.open_group("initial"), file.root().create_group("initial"), r.orbits);
    return execute(r, e, output, file, interrupt, options, log);
  } catch (const Error& e) {
    if (e.code() != ExitCode::io) throw;
    throw Error(ExitCode::io, "checkpoint '" + path + "': " + e.what());
  }
}

}  // namespace

int run_command(const RunOptions& options, std::ostream& log) {
  // A signal from here on is answered after the first segment: the run stops with a checkpoint.
  const InterruptGuard interrupt;
  if (!options.resume.empty()) return resume_command(options, interrupt, log);
  if (options.config_path.empty() && options.config_source.empty())
    throw usage_error("qmaps run needs a config file, or --resume <output>.ckpt");
  const std::string started = utc_now();
  Config config = options.config_path.empty()
                      ? Config::parse(options.config_text, options.config_source)
                      : Config::load(options.config_path);
  for (const auto& s : options.sets) config.set(s);
  // A shard's --out names its own file: the configuration keeps the whole run's output, which
  // every shard of the run must share.
  if (!options.out.empty() && options.shard.empty()) config.set("output.file=" + options.out);

  auto model = map_of(config, chaos_options_of(config));
  if (const auto sweep = Sweep::from_config(config, *model)) {
    if (!options.shard.empty()) throw usage_error("--shard splits a run's orbits, not a sweep's points");
    return run_sweep(config, *sweep, options, started, interrupt, log);
  }
  const auto initial_conditions = options.points
                                      ? InitialConditions::of_points(config, options.points)
                                      : InitialConditions::from_config(config, *model);
  Run r = run_of(config, std::move(model), initial_conditions.orbits(), options);
  r.kind = initial_conditions.kind();
  r.rejects_points = initial_conditions.generator().rejects_points();
  r.description = initial_conditions.description();
  r.seed = initial_conditions.seed();
  r.command_line = options.command_line;
  r.started = started;
  config.reject_unknown();

  h5::AtomicFile output(r.path);
  auto file = output.create_hdf5(r.deflate);  // fails now, not after the run
  const OutputLock lock(r.path);              // a second run to this output is refused

  // The orbits start by parts; /initial is written as they do, and no full copy is kept.
  Ensemble e = r.model->ensemble(r.orbits);
  const auto initial = r.per_orbit ? std::optional(file.root().create_group("initial")) : std::nullopt;
  if (initial) create_phase(*initial, r.orbits);
  r.rejected = initial_conditions.start(
      *r.model, e, r.start, r.plan.escape_bound,
      [&](std::size_t first, std::span<const Phase> points) {
        if (initial) write_phase_part(*initial, first, points);
      },
      orbits_per_part, r.first);
  for (auto& t : r.trajectories) record(t, *r.model, e, r.plan);
  return execute(r, e, output, file, interrupt, options, log);
}

}  // namespace qmaps
