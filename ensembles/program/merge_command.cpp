// `qmaps merge SHARDS... --out FILE`: joins the shard files of one run (`qmaps run --shard k/K`)
// into the file the whole run writes, dataset for dataset. The shards must belong together: the
// same resolved configuration, the same K, each of 1 … K once, each complete. Every shard is
// read as a checkpoint is (its state, escapes, invariant tracking, observers, trajectories) and
// placed at its orbits' offset; the run's file is then written from the whole ensemble.
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <ostream>
#include <vector>

#include "core/error.hpp"
#include "ensembles/io/h5.hpp"
#include "core/memory_limit.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/observer_config.hpp"
#include "ensembles/config/shard.hpp"
#include "ensembles/io/checkpoint.hpp"
#include "ensembles/io/output.hpp"
#include "ensembles/io/run_observers/run_observers.hpp"
#include "ensembles/io/output_lock.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/run_setup.hpp"
#include "ensembles/program/run_spec.hpp"

namespace qmaps {
namespace {

// A shard as the set's check reads it; its file is opened again when its orbits are read, one
// shard at a time (a merge of thousands of shards holds one file open).
struct ShardFile {
  std::string path;
  Shard shard;
  std::string config_resolved;
  std::int64_t orbits_total = 0;
};

Error refused(const std::string& what) { return Error(ExitCode::usage, "qmaps merge: " + what); }

// read() of the shard at `path`: a file error names the shard.
template <class Read>
void reading(const std::string& path, Read read) {
  try {
    read();
  } catch (const Error& failure) {
    if (failure.code() != ExitCode::io) throw;
    throw Error(ExitCode::io, "'" + path + "': " + failure.what());
  }
}

// The shards, checked to be every one of one run, ordered by k; any other set is refused.
std::vector<ShardFile> shard_set(const std::vector<std::string>& paths) {
  std::vector<ShardFile> shards;
  for (const auto& path : paths) {
    const h5::File file = h5::File::open_read(path);
    const auto root = file.root();
    if (!root.has_attr("shard") || !root.has_attr("config_resolved"))
      throw refused("'" + path + "' is not a shard file (it has no attribute shard)");
    if (root.has_attr("checkpoint_version"))
      throw refused("'" + path + "' is a shard's checkpoint: finish it with qmaps run --resume");
    reading(path, [&] {
      Shard shard;
      try {
        shard = Shard::parse(root.attr_string("shard"));
      } catch (const Error& e) {
        throw Error(ExitCode::io, "attribute shard: " + std::string(e.what()));
      }
      shards.push_back({path, shard, root.attr_string("config_resolved"),
                        root.attr_int64("orbits_total")});
    });
  }
  const auto& first = shards.front();
  for (const auto& s : shards) {
    if (s.config_resolved != first.config_resolved || s.orbits_total != first.orbits_total)
      throw refused("'" + s.path + "' is a shard of another run than '" + first.path +
                    "' (their configurations differ)");
    if (s.shard.count != first.shard.count)
      throw refused("'" + s.path + "' is shard " + s.shard.name() + ", '" + first.path +
                    "' shard " + first.shard.name() + ": not one split");
  }
  std::sort(shards.begin(), shards.end(),
            [](const ShardFile& a, const ShardFile& b) { return a.shard.index < b.shard.index; });
  for (std::size_t i = 1; i < shards.size(); ++i)
    if (shards[i].shard.index == shards[i - 1].shard.index)
      throw refused("'" + shards[i - 1].path + "' and '" + shards[i].path + "' are both shard " +
                    shards[i].shard.name());
  std::string missing;
  std::size_t at = 0, count = 0;
  for (std::size_t k = 1; k <= first.shard.count; ++k) {
    if (at < shards.size() && shards[at].shard.index == k) {
      ++at;
      continue;
    }
    if (++count <= 10) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
  }
  if (count > 0)
    throw refused(std::to_string(count) + " of the " + std::to_string(first.shard.count) +
                  " shards " + (count == 1 ? "is" : "are") + " missing: " + missing +
                  (count > 10 ? ", ..." : ""));
  return shards;
}

// Refuses, before reading, a merge that cannot fit: the whole run's memory and, besides it, the
// section points of the largest shard while they are placed.
void check_memory(const Run& r, std::size_t orbits, std::size_t largest) {
  const double bytes = memory_of(r) + r.observers.bytes(r.x.threads) *
                                          static_cast<double>(largest) / static_cast<double>(orbits);
  check_fits(bytes, "qmaps merge",
             std::to_string(orbits) + " orbits, with the largest shard's section points,");
}

// The merged file is none of its shards, by name or by file.
void refuse_an_input_as_output(const MergeOptions& options) {
  struct stat out {};
  const bool exists = ::stat(options.out.c_str(), &out) == 0;
  for (const auto& path : options.shards) {
    struct stat in {};
    if (path == options.out ||
        (exists && ::stat(path.c_str(), &in) == 0 && in.st_dev == out.st_dev && in.st_ino == out.st_ino))
      throw refused("--out '" + options.out + "' is the shard '" + path +
                    "' given to merge: name a file of its own");
  }
}

}  // namespace

int merge_command(const MergeOptions& options, std::ostream& log) {
  check_output_name(options.out, "--out");
  refuse_an_input_as_output(options);
  std::vector<ShardFile> shards = shard_set(options.shards);
  const auto total = shards.front().orbits_total;
  if (total <= 0) throw Error(ExitCode::io, "'" + shards.front().path + "': attribute orbits_total is " + std::to_string(total));
  const auto orbits = static_cast<std::size_t>(total);
  SpecSource whole;
  whole.threads = 1;
  whole.simd = "scalar";
  RunSpec spec = read_recorded_spec(shards.front().config_resolved,
                                    shards.front().path + " (config_resolved)", orbits, whole);
  const Config& config = spec.config;
  Run& r = spec.points.front().run;
  std::size_t largest = 0;
  for (const auto& s : shards) largest = std::max(largest, s.shard.size(orbits));
  check_memory(r, orbits, largest);
  r.path = options.out;
  reading(shards.front().path, [&] {
    const h5::File head = h5::File::open_read(shards.front().path);
    read_provenance(head.root(), r);
  });

  const OutputLock lock(r.path);  // first: a second run to this output is refused
  h5::AtomicFile output(r.path);
  auto file = output.create_hdf5(r.deflate);
  const auto initial = r.per_orbit ? std::optional(file.root().create_group("initial")) : std::nullopt;
  if (initial) create_phase(*initial, orbits);

  Ensemble e = r.model->ensemble(orbits, r.measured);
  MeasuredOutput kept = describe_kept(record_of(r, e, 0, "", "", ""));  // the shards' add up here
  std::string finished;
  for (const ShardFile& s : shards) {
    const h5::File file = h5::File::open_read(s.path);
    const auto root = file.root();
    const std::size_t first = s.shard.first(orbits), n = s.shard.size(orbits);
    reading(s.path, [&] {
      check_record_of(root, r);
      if (root.attr_int64("orbits") != static_cast<std::int64_t>(n) ||
          root.attr_int64("shard_first") != static_cast<std::int64_t>(first))
        throw Error(ExitCode::io, "its orbits are not shard " + s.shard.name() + "'s " +
                                      std::to_string(first) + " to " + std::to_string(first + n - 1));
      read_ensemble(root, *r.model, e, Rows{0, n, n}, first);
      if (e.step != r.plan.total)
        throw Error(ExitCode::io, "it stopped at step " + std::to_string(e.step) + " of " +
                                      std::to_string(r.plan.total));
      // The shard's observers and trajectories (of its orbits), as its run made them.
      Observers observers = observers_from_config(config, *r.model, n, r.plan.total);
      std::vector<Trajectory> trajectories = r.trajectories;
      keep_orbits_in(trajectories, first, n);
      RunRecord shard_record = record_of(r, e, 0, "", "", "");
      shard_record.observers = &observers;
      shard_record.trajectories = &trajectories;
      MeasuredOutput shard_kept = describe_kept(shard_record);
      restore_kept(root, shard_kept);
      add_part(kept, shard_kept, first);
      if (initial) {
        const auto from = root.open_group("initial");
        std::vector<Phase> points(std::min(n, orbits_per_part));
        for (std::size_t i = 0; i < n; i += orbits_per_part) {
          const auto some = std::span<Phase>(points).first(std::min(orbits_per_part, n - i));
          read_phase_part(from, i, n, some);
          write_phase_part(*initial, first + i, some);
        }
      }
      r.rejected += static_cast<std::uint64_t>(root.attr_int64("rejected"));
      r.sessions += root.attr_string("sessions");
      finished = std::max(finished, root.attr_string("finished"));
    });
  }
  e.step = r.plan.total;
  e.fill_padding();
  r.observers.finish();
  naming_failures(r.path, [&] {
    RunRecord record = record_of(r, e, 0, r.started, finished, r.command_line);
    record.sessions = r.sessions;  // the shards' sessions: the merge steps nothing
    record.finished = finished;
    write_run(file.root(), record);
    file.close();
  });
  output.commit();
  log << "qmaps: merged " << shards.size() << " shards, " << orbits << " orbits x "
      << r.plan.total << " steps, " << e.escaped() << " escaped -> " << r.path << '\n';
  return 0;
}

}  // namespace qmaps
