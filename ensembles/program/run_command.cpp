#include <omp.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <csignal>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <optional>
#include <ostream>

#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "core/error.hpp"
#include "core/io/h5.hpp"
#include "kernels/catalogue.hpp"
#include "ensembles/io/checkpoint.hpp"
#include "ensembles/program/commands.hpp"
#include "core/memory_limit.hpp"
#include "core/tangent_map.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/io/output.hpp"
#include "ensembles/io/output_lock.hpp"
#include "ensembles/program/progress.hpp"

namespace qmaps {
namespace {

// [chaos], if the run records chaos indicators (docs/chaos.md).
std::optional<ChaosOptions> chaos_options_of(const Config& config) {
  if (!config.has_section("chaos")) return std::nullopt;
  ChaosOptions o;
  o.spectrum = config.boolean_or("chaos", "spectrum", false);
  o.every = config.integer_or("chaos", "orthonormalize_every", o.every);
  if (o.every < 1 || o.every > max_orthonormalize_every)
    throw usage_error(config.where("chaos", "orthonormalize_every") + " must be 1 to " +
                      std::to_string(max_orthonormalize_every) + " (got " +
                      std::to_string(o.every) + ")");
  return o;
}

// How the output classifies and histograms the indicators.
ChaosReport chaos_report_of(const Config& config) {
  ChaosReport report;
  report.megno_threshold = config.number_or("chaos", "megno_threshold", report.megno_threshold);
  if (!(report.megno_threshold > 0 && report.megno_threshold < 1e300))
    throw usage_error(config.where("chaos", "megno_threshold") + " must be a positive number");
  report.bins = config.integer_or("chaos", "bins", report.bins);
  if (report.bins < 1 || report.bins > (1 << 20))
    throw usage_error(config.where("chaos", "bins") + " must be 1 to 1048576");
  return report;
}


// The memory a run holds per orbit: the state (with its chaos record), the escape record (step,
// reason), the invariant tracking (initial value, max drift), the chaos indicators computed for
// the output; the observers count theirs (Observers::bytes).
double bytes_per_orbit(const Model& model) {
  return static_cast<double>(8 * model.state_names().size() + 9 +
                             16 * model.invariant_names().size() +
                             8 * model.indicator_names().size());
}

// Refuses, before allocating, a run that cannot fit in this machine's memory: its orbits and
// its observers (Observers::bytes: the histograms in every thread, the sections' point slots).
void check_memory(const Config& config, const Model& model, std::size_t orbits,
                  double for_observers) {
  const double padded = static_cast<double>((orbits + Ensemble::padding - 1) /
                                            Ensemble::padding * Ensemble::padding);
  const double for_orbits = padded * bytes_per_orbit(model);
  const MemoryLimit have = memory_limit();
  if (for_orbits + for_observers <= have.bytes) return;
  // The key that sets the ensemble's size: a grid's points, else its orbits.
  const char* key = config.has("ensemble", "points") ? "points" : "orbits";
  char text[300];
  std::snprintf(text, sizeof text, ": %zu orbits need about %.3g GiB", orbits,
                for_orbits / (1 << 30));
  std::string message = config.where("ensemble", key) + text;
  if (for_observers > 0) {
    std::snprintf(text, sizeof text,
                  ", and their histograms (a copy per thread), section points and trajectories "
                  "%.3g GiB",
                  for_observers / (1 << 30));
    message += text;
  }
  std::snprintf(text, sizeof text, "; %s is %.3g GiB", have.what.c_str(), have.bytes / (1 << 30));
  throw usage_error(message + text);
}

// A run as its resolved configuration and the command line describe it (the ensemble aside).
struct Run {
  std::unique_ptr<Model> model;
  std::size_t orbits = 0;
  Start start = Start::taylor;
  RunPlan plan;
  Execution x;
  long long checkpoint_every = 0;  // 0: only when interrupted
  bool per_orbit = true;
  int deflate = 0;  // [output] compression: the gzip level, 0 for none
  Observers observers;
  std::optional<InvariantImage> image;
  ChaosReport chaos;
  std::vector<Trajectory> trajectories;
  std::string path;  // the output file
  std::string kind, description;  // the ensemble's kind and its one-line description
  std::uint64_t seed = 0;
  std::uint64_t rejected = 0;  // candidates rejected while drawing it (shell ensembles)
  bool rejects_points = false;  // the kind rejects candidates: the summary says how many
  // Provenance carried over from the first session (and the checkpoints).
  std::string config_text, config_resolved, command_line, started, sessions;
  // When this session began: the summary splits its time into starting (configuration, initial
  // conditions or the checkpoint), stepping (with the observers) and writing the output.
  std::chrono::steady_clock::time_point began = std::chrono::steady_clock::now();
};

Run run_of(const Config& config, std::unique_ptr<Model> model, std::size_t orbits,
           const RunOptions& options) {
  Run r;
  r.model = std::move(model);
  r.orbits = orbits;
  check_memory(config, *r.model, orbits, 0);  // before the observers are made
  try {
    r.start = parse_start(config.string_or("ensemble", "start", "taylor"));
  } catch (const Error& e) {
    throw usage_error(config.where("ensemble", "start") + ": " + e.what());
  }

  r.plan.total = r.plan.last = config.integer("run", "steps");
  if (r.plan.total < 0) throw usage_error(config.where("run", "steps") + " must be >= 0");
  r.plan.stride = config.integer_or("run", "stride", 1);
  if (r.plan.stride < 1) throw usage_error(config.where("run", "stride") + " must be >= 1");
  r.plan.escape_bound = config.number_or("run", "escape_bound", r.plan.escape_bound);
  if (!(r.plan.escape_bound > 0))
    throw usage_error(config.where("run", "escape_bound") + " must be > 0");
  r.checkpoint_every = config.integer_or("run", "checkpoint_every", 0);
  if (r.checkpoint_every < 0)
    throw usage_error(config.where("run", "checkpoint_every") + " must be >= 0 (0: never)");

  r.x.isa = resolve_isa(options.simd);
  r.x.threads =
      r.x.isa == Isa::scalar ? 1 : options.threads > 0 ? options.threads : omp_get_max_threads();
  r.x.chains = static_cast<int>(config.integer_or("run", "chains", Execution{}.chains));
  if (r.x.chains != 1 && r.x.chains != 2 && r.x.chains != 4 && r.x.chains != 8)
    throw usage_error(config.where("run", "chains") + " must be 1, 2, 4 or 8");

  r.observers = observers_from_config(config, *r.model, orbits, r.plan.total);
  r.trajectories = trajectories_from_config(config, *r.model, orbits, r.plan.total);
  double for_trajectories = 0;
  for (const auto& t : r.trajectories) for_trajectories += t.bytes(r.plan.total);
  check_memory(config, *r.model, orbits, r.observers.bytes(r.x.threads) + for_trajectories);
  r.image = invariant_image_from_config(config, *r.model);
  r.chaos = chaos_report_of(config);

  r.path = config.string("output", "file");
  // Every name the run derives from the output's must be legal before the run starts: the
  // longest is the checkpoint's temporary, "<name>.ckpt.tmp-<pid>".
  const auto slash = r.path.rfind('/');
  const std::string name = slash == std::string::npos ? r.path : r.path.substr(slash + 1);
  const std::size_t longest = name.size() + std::strlen(checkpoint_suffix) + std::strlen(".tmp-") + 10;
  if (name.empty() || longest > NAME_MAX)
    throw usage_error(config.where("output", "file") + ": the name '" + name + "' has " +
                      std::to_string(name.size()) + " bytes; its checkpoint's temporary needs " +
                      std::to_string(longest - name.size()) + " more and a name may have at most " +
                      std::to_string(NAME_MAX));
  if (r.path.empty()) throw usage_error(config.where("output", "file") + " must not be empty");
  r.per_orbit = config.boolean_or("output", "per_orbit", true);
  const std::string compression = config.string_or("output", "compression", "none");
  if (compression != "none" && compression != "gzip")
    throw usage_error(config.where("output", "compression") + ": '" + compression +
                      "' is not a compression (expected \"none\" or \"gzip\")");
  if (compression == "gzip") {
    const long long level = config.integer_or("output", "compression_level", 4);
    if (level < 1 || level > 9)
      throw usage_error(config.where("output", "compression_level") + " must be 1 to 9 (got " +
                        std::to_string(level) + ")");
    r.deflate = static_cast<int>(level);
  } else if (config.has("output", "compression_level")) {
    throw usage_error(config.where("output", "compression_level") +
                      " needs compression = \"gzip\"");
  }
  r.config_text = config.text();
  r.config_resolved = config.resolved();
  return r;
}

// The record of the run with the ensemble where it is now, this session ended at `now`.
RunRecord record_of(const Run& r, const Ensemble& e, long long session_first,
                    const std::string& session_started, const std::string& now,
                    const std::string& session_command) {
  return RunRecord{*r.model, e, r.plan, r.x, r.kind, r.seed, r.start, r.per_orbit,
                   r.config_text, r.config_resolved, r.command_line, r.started, now,
                   r.sessions + session_line(session_first, e.step, r.x, session_started, now,
                                             session_command),
                   &r.observers, r.image ? &*r.image : nullptr, r.description, r.rejected,
                   r.chaos, &r.trajectories};
}

// Runs `write`, which writes the file at `path`; an io failure there names the file and, where
// the system said why (no space left on device, file too large), the reason.
template <class Write>
void naming_failures(const std::string& path, Write write) {
  try {
    errno = 0;
    write();
  } catch (const Error& failure) {
    if (failure.code() != ExitCode::io) throw;
    const int err = errno;
    throw Error(ExitCode::io, "cannot write '" + path + "': " + failure.what() +
                                  (err ? std::string(" (") + std::strerror(err) + ")" : ""));
  }
}

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
    if (e.step == r.plan.total) break;
    self_signal.deliver_if_due(e.step);
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
    const auto orbits = root.attr_int64("orbits");
    if (orbits <= 0) throw Error(ExitCode::io, "attribute orbits is " + std::to_string(orbits));
    Run r = run_of(config, map_of(config, chaos_options_of(config)),
                   static_cast<std::size_t>(orbits), options);
    r.path = path.substr(0, path.size() - suffix.size());
    r.kind = root.attr_string("ensemble");
    r.seed = static_cast<std::uint64_t>(root.attr_int64("seed"));
    r.description = root.attr_string("ensemble_description");
    r.rejected = static_cast<std::uint64_t>(root.attr_int64("rejected"));
    r.rejects_points = r.rejected > 0;  // the kind itself is not rebuilt on resumption
    r.config_text = root.attr_string("config");
    r.command_line = root.attr_string("command_line");
    r.started = root.attr_string("started");
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
  if (options.config_path.empty())
    throw usage_error("qmaps run needs a config file, or --resume <output>.ckpt");
  const std::string started = utc_now();
  Config config = Config::load(options.config_path);
  for (const auto& s : options.sets) config.set(s);
  if (!options.out.empty()) config.set("output.file=" + options.out);

  auto model = map_of(config, chaos_options_of(config));
  const auto initial_conditions = InitialConditions::from_config(config, *model);
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
      orbits_per_part);
  for (auto& t : r.trajectories) record(t, *r.model, e, r.plan);
  return execute(r, e, output, file, interrupt, options, log);
}

}  // namespace qmaps
