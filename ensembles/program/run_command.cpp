#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <ostream>

#include "core/error.hpp"
#include "ensembles/io/h5.hpp"
#include "ensembles/io/ranks.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/io/checkpoint.hpp"
#include "ensembles/io/output.hpp"
#include "ensembles/io/output_lock.hpp"
#include "ensembles/io/run_observers/run_observers.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/segments.hpp"
#include "ensembles/program/session.hpp"
#include "ensembles/program/every_rank.hpp"
#include "ensembles/program/run_setup.hpp"
#include "ensembles/program/run_spec.hpp"
#include "ensembles/program/sweep_run.hpp"

namespace qmaps {
namespace {

// Every rank runs the same configuration into the same file.
void check_same_run(const Run& r) {
  const std::string mine = r.config_resolved + "\n" + r.path;
  if (ranks::from_root(mine) != mine)
    throw usage_error("the ranks' configurations differ (or their outputs): rank " +
                      std::to_string(ranks::rank()) + " runs another than rank 0");
}

// Over several ranks, a failure once the ranks write together (where the others cannot be told,
// as they may wait in a collective write) ends every rank at once, the output's temporary
// removed: `work` runs under this guard.
template <class Work>
int ending_every_rank_on_failure(const h5::AtomicFile& output, Work work) {
  if (ranks::count() == 1) return work();
  try {
    return work();
  } catch (const std::exception& e) {
    const auto* error = dynamic_cast<const Error*>(&e);
    const auto* interrupted = dynamic_cast<const Interrupted*>(&e);
    std::fprintf(stderr, "qmaps: rank %d: %s%s\n", ranks::rank(),
                 error && !interrupted ? "error: " : "", e.what());
    std::remove(output.temporary().c_str());
    ranks::abort(interrupted ? 128 + interrupted->signal()
                 : error     ? static_cast<int>(error->code())
                             : static_cast<int>(ExitCode::failure));
  }
}

// The output written after the last step: where it fails (a full disk, a rename the folder no
// longer permits), the run's checkpoint is written instead, so that no stepping is lost.
template <class Save, class Write>
void keeping_the_work_on_failure(const Run& r, const std::string& checkpoint, Save save,
                                 Write write) {
  try {
    write();
  } catch (const Error& failure) {
    if (failure.code() != ExitCode::io) throw;
    const std::string resume = "; continue with: qmaps run --resume " + checkpoint;
    try {
      save();
    } catch (const Error& also) {
      throw Error(ExitCode::io, std::string(failure.what()) +
                                    "; the run's checkpoint could not be written either: " +
                                    also.what());
    }
    throw Error(ExitCode::io, std::string(failure.what()) + "; the run (step " +
                                  std::to_string(r.plan.total) + ") is kept in its checkpoint " +
                                  checkpoint + resume);
  }
}

// Advances the ensemble to the last step in segments (exact: a segmented run equals one call),
// writing a checkpoint every `checkpoint_every` steps and, on SIGINT, SIGTERM or SIGHUP, one
// before it stops; then writes the output file and removes the checkpoint.
int execute(Run& r, Ensemble& e, h5::AtomicFile& output, h5::File& file,
            const InterruptGuard& interrupt, const SessionOptions& session, std::ostream& log) {
  const auto since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  const double starting = since(r.began);
  const std::string session_started = r.sessions.empty() ? r.started : utc_now();
  const long long first = e.step;
  const std::string checkpoint = r.path + checkpoint_suffix;
  const auto initial = r.per_orbit ? std::optional(file.root().open_group("initial")) : std::nullopt;
  // The checkpoint, its /initial copied from `from` (the output's, being written).
  const auto save_from = [&](const h5::Group* from) {
    r.observers.finish();
    naming_failures(checkpoint, [&] {
      write_checkpoint(checkpoint,
                       record_of(r, e, first, session_started, utc_now(), session.command_line),
                       from);
    });
  };
  const auto save = [&] { save_from(initial ? &*initial : nullptr); };

  const std::size_t orbits = r.shard ? r.orbits : r.total;  // the file's
  const SessionPart part{r, e};
  const auto [signal, seconds] =
      step_session(std::span(&part, 1), SegmentLoop::run_aim, r.checkpoint_every, orbits, session,
                   interrupt, log, [&](long long step) {
                     if (r.checkpoint_every > 0 && step % r.checkpoint_every == 0) save();
                   });
  if (signal != 0) {
    // Stopped, the run writes no output: its temporary goes at once, before the checkpoint, so
    // that a kill in what remains (mpirun's SIGKILL, 1 s after it passed SIGTERM on to the
    // ranks) leaves none behind.
    output.discard();
    if (!session.checkpoint_on_interrupt) {
      log << "qmaps: " << interrupt.named(signal) << " at step " << e.step << " of "
          << r.plan.total << ": stopped, nothing written\n";
      return static_cast<int>(ExitCode::interrupted);
    }
    save();
    if (ranks::root())
      log << "qmaps: " << interrupt.named(signal) << " at step " << e.step << " of " << r.plan.total
          << ": checkpoint written to " << checkpoint
          << "; continue with: qmaps run --resume " << checkpoint << '\n';
    return static_cast<int>(ExitCode::interrupted);
  }
  const auto writing_began = std::chrono::steady_clock::now();
  r.observers.finish();
  const auto write = [&] {
    naming_failures(r.path, [&] {  // an incomplete file is never committed
      const RunRecord record = record_of(r, e, first, session_started, utc_now(), session.command_line);
      write_run(file.root(), record);
      if (r.shard) write_kept(file.root(), describe_kept(record));  // for qmaps merge
      file.close();
    });
  };
  // Over several ranks a write that fails on one rank alone ends them all
  // (ending_every_rank_on_failure); the rename's failure is every rank's.
  if (ranks::count() == 1) keeping_the_work_on_failure(r, checkpoint, save, write);
  else write();
  // The output is complete, and closed, at its temporary: the checkpoint's /initial is read back.
  const auto save_after_writing = [&] {
    if (!initial) return save_from(nullptr);
    const auto written = h5::File::open_read(output.temporary());
    const auto points = written.root().open_group("initial");
    save_from(&points);
  };
  keeping_the_work_on_failure(r, checkpoint, save_after_writing, [&] { output.commit(); });
  if (ranks::root()) std::remove(checkpoint.c_str());
  const double writing = ranks::max(since(writing_began));
  const double stepping = ranks::max(seconds), started_in = ranks::max(starting);
  const auto escaped = ranks::sum(static_cast<std::int64_t>(e.escaped()));
  const auto rejected = ranks::sum(static_cast<std::int64_t>(r.rejected));
  if (!ranks::root()) return 0;

  log << summary_line(r, 0, orbits, r.plan.total - first, stepping, escaped, rejected);
  char line[512];
  std::snprintf(line, sizeof line,
                "qmaps: time by phase: starting %.3f s, stepping and observing %.3f s, writing "
                "%.3f s\n",
                started_in, stepping, writing);
  log << line;
  return 0;
}

// Rank 0's trajectories over several ranks: each of their orbits started alone, as orbit i of the
// ensemble starts whatever the orbits around it, and recorded from there.
void record_alone(Run& r, const InitialConditions& initial_conditions) {
  for (auto& t : r.trajectories) {
    Ensemble few = r.model->ensemble(t.orbits.size());
    for (std::size_t j = 0; j < t.orbits.size(); ++j) {
      Ensemble one = r.model->ensemble(1);
      initial_conditions.start(*r.model, one, r.start, r.plan.escape_bound,
                               [](std::size_t, std::span<const Phase>) {}, 1, t.orbits[j]);
      few.set_orbit(j, one, 0);
    }
    few.fill_padding();
    const std::vector<std::size_t> orbits = t.orbits;
    for (std::size_t j = 0; j < orbits.size(); ++j) t.orbits[j] = j;
    record(t, *r.model, few, r.plan);
    t.orbits = orbits;
    for (auto& o : t.orbit) o = static_cast<std::int64_t>(orbits[static_cast<std::size_t>(o)]);
  }
}

// A fresh run never replaces the checkpoint of an interrupted one: that is resumed, or removed
// by the user.
void refuse_an_unresumed_checkpoint(const std::string& output) {
  const std::string checkpoint = output + checkpoint_suffix;
  struct stat info {};
  if (::lstat(checkpoint.c_str(), &info) == 0)
    throw Error(ExitCode::io, "output '" + output + "' has the checkpoint '" + checkpoint +
                                  "' of an interrupted run: continue it with qmaps run --resume " +
                                  checkpoint + ", or remove it to start afresh");
}

int resume_command(const RunOptions& options, const InterruptGuard& interrupt,
                   std::ostream& log) {
  if (!options.source.config_path.empty() || !options.source.sets.empty() ||
      !options.source.out.empty())
    throw usage_error(
        "--resume continues the run its checkpoint describes: give no config, --set or --out");
  const std::string& path = options.resume;
  const std::string suffix = checkpoint_suffix;
  if (path.size() <= suffix.size() || path.compare(path.size() - suffix.size(), suffix.size(), suffix) != 0)
    throw usage_error("--resume " + path + ": a checkpoint is named <output>" + suffix);

  std::optional<h5::File> checkpoint;
  std::optional<RunSpec> spec;
  const auto reading = [&](auto read) {
    try {
      read();
    } catch (const Error& e) {
      if (e.code() != ExitCode::io) throw;
      throw Error(ExitCode::io, "checkpoint '" + path + "': " + e.what());
    }
  };
  on_every_rank([&] {
    checkpoint = open_checkpoint(path);
    const auto root = checkpoint->root();
    reading([&] {
      // A shard's checkpoint resumes the shard: its range of the ensemble's orbits.
      SpecSource resumed = options.source;
      const bool shard = root.has_attr("shard");
      if (shard && ranks::count() > 1)
        throw usage_error("--resume " + path + ": a shard's checkpoint resumes in one process");
      if (shard) resumed.shard = root.attr_string("shard");
      const auto orbits = root.attr_int64(shard ? "orbits_total" : "orbits");
      if (orbits <= 0) throw Error(ExitCode::io, "attribute orbits is " + std::to_string(orbits));
      spec = read_recorded_spec(root.attr_string("config_resolved"), path + " (config_resolved)",
                                static_cast<std::size_t>(orbits), resumed);
      Run& r = spec->points.front().run;
      if (r.shard && static_cast<std::int64_t>(r.orbits) != root.attr_int64("orbits"))
        throw Error(ExitCode::io, "attribute orbits is " + std::to_string(root.attr_int64("orbits")) +
                                      "; shard " + r.shard->name() + " has " + std::to_string(r.orbits));
      r.path = path.substr(0, path.size() - suffix.size());
      read_provenance(root, r);
      check_record_of(root, r);
      // The candidates rejected so far, counted once over the ranks.
      r.rejected = ranks::root() ? static_cast<std::uint64_t>(root.attr_int64("rejected")) : 0;
      r.rejects_points = root.attr_int64("rejected") > 0;  // the kind is not rebuilt on resumption
      r.sessions = root.attr_string("sessions");
    });
  });
  Run& r = spec->points.front().run;
  const auto root = checkpoint->root();
  std::optional<OutputLock> lock;  // first: a second run to this output is refused
  on_every_rank([&] {
    if (ranks::root()) lock.emplace(r.path);
  });
  h5::AtomicFile output(r.path);
  auto file = output.create_hdf5(r.deflate);
  return ending_every_rank_on_failure(output, [&] {
    Ensemble e = r.model->ensemble(r.orbits, r.measured);
    const Rows rows = r.shard ? Rows{} : Rows{r.first, r.orbits, r.total};
    reading([&] {
      read_ensemble(root, *r.model, e, rows);
      // A checkpoint at the last step is one the output's writing failed after (it is written).
      if (e.step < 0 || e.step > r.plan.total)
        throw Error(ExitCode::io, "its step " + std::to_string(e.step) + " is not in [0, " +
                                      std::to_string(r.plan.total) + "]");
      MeasuredOutput kept = describe_kept(record_of(r, e, e.step, "", "", ""));
      restore_kept(root, kept, rows);  // the trajectories on rank 0
      if (!ranks::root())
        for (auto& t : r.trajectories) record(t, *r.model, e, r.plan);  // of none of its orbits
      if (r.per_orbit)
        copy_phase(root.open_group("initial"), file.root().create_group("initial"),
                   rows.or_all(r.orbits));
    });
    return execute(r, e, output, file, interrupt, options.session, log);
  });
}

}  // namespace

int run_command(const RunOptions& options, std::ostream& log) {
  // A signal from here on is answered after the first segment: the run stops with a checkpoint.
  const InterruptGuard interrupt;
  if (!options.resume.empty()) return resume_command(options, interrupt, log);
  RunSpec spec = read_spec(options.source);
  return run_spec(spec, options.session, interrupt, log);
}

int run_spec(RunSpec& spec, const SessionOptions& session, const InterruptGuard& interrupt,
             std::ostream& log) {
  if (spec.ran) throw usage_error("a run's spec runs once: read it again to run it again");
  spec.ran = true;
  for (RunPoint& p : spec.points) p.run.command_line = session.command_line;  // the run's first
  if (spec.sweep) return run_sweep(spec, session, interrupt, log);
  const InitialConditions* initial_conditions = &*spec.points.front().initial;
  Run& r = spec.points.front().run;
  if (ranks::count() > 1) on_every_rank([&] { check_same_run(r); });

  std::optional<OutputLock> lock;  // first: a second run to this output is refused
  on_every_rank([&] {
    if (!ranks::root()) return;
    lock.emplace(r.path);
    refuse_an_unresumed_checkpoint(r.path);
  });
  h5::AtomicFile output(r.path);
  auto file = output.create_hdf5(r.deflate);  // fails now, not after the run

  return ending_every_rank_on_failure(output, [&] {
    // The orbits start by parts; /initial is written as they do, and no full copy is kept.
    Ensemble e = r.model->ensemble(r.orbits, r.measured);
    const auto initial =
        r.per_orbit ? std::optional(file.root().create_group("initial")) : std::nullopt;
    const std::size_t rows = r.shard ? r.orbits : r.total;
    const std::size_t at = r.shard ? 0 : r.first;  // this process's first row of the file
    if (initial) create_phase(*initial, rows);
    std::size_t parts = 0;
    r.rejected = initial_conditions->start(
        *r.model, e, r.start, r.plan.escape_bound,
        [&](std::size_t first, std::span<const Phase> points) {
          if (initial) write_phase_part(*initial, at + first, points);
          ++parts;
        },
        orbits_per_part, r.first);
    // As many writes on every rank (ensembles/io/h5.hpp): the ranks with fewer parts write empty ones.
    if (initial)
      for (std::size_t more = parts_of(r.orbits); parts < more; ++parts)
        write_phase_part(*initial, at, {});
    if (ranks::count() > 1 && ranks::root()) record_alone(r, *initial_conditions);
    else
      for (auto& t : r.trajectories) record(t, *r.model, e, r.plan);
    return execute(r, e, output, file, interrupt, session, log);
  });
}

}  // namespace qmaps
