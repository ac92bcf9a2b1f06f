#pragma once
// A run as its resolved configuration and the command line describe it: the model, the plan, the
// path, the observers and the output's options, checked before anything is allocated. qmaps run
// makes one (ensembles/program/run_command.cpp), a sweep one per point (sweep_command.cpp).
#include <chrono>
#include <cerrno>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/model.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/observer_config.hpp"
#include "ensembles/config/shard.hpp"
#include "ensembles/io/output.hpp"
#include "ensembles/io/trajectories.hpp"
#include "ensembles/program/commands.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {

// [chaos], if the run records chaos indicators (docs/chaos.md).
std::optional<ChaosOptions> chaos_options_of(const Config& config);

// The optional lane measurements (core/observers/lane_observers.hpp) the configuration turns on:
// each whose table it has.
std::vector<std::string> measured_of(const Config& config, const Model& model);

// The memory a run holds per orbit besides its observers.
double bytes_per_orbit(const Model& model, std::span<const std::string> measured);

// A run as its resolved configuration and the command line describe it (the ensemble aside).
struct Run {
  std::unique_ptr<Model> model;
  std::size_t orbits = 0;  // the orbits it runs: the ensemble's, or a shard's range of them
  std::optional<Shard> shard;       // --shard k/K: orbits [first, first + orbits) of `total`
  std::size_t first = 0, total = 0;
  Start start = Start::taylor;
  RunPlan plan;
  Execution x;
  long long checkpoint_every = 0;  // 0: only when interrupted
  bool per_orbit = true;
  int deflate = 0;  // [output] compression: the gzip level, 0 for none
  std::vector<std::string> measured;  // the optional lane measurements it takes (measured_of)
  Observers observers;
  std::optional<InvariantImage> image;
  ChaosReport chaos;
  TuneReport tunes;
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

// Reads everything of [run], [output], [chaos] and the observers' tables for an ensemble of
// `orbits` orbits of `model` (with --shard, for its range of them); every error names its key.
// The ensemble itself is the caller's.
Run run_of(const Config& config, std::unique_ptr<Model> model, std::size_t orbits,
           const SpecSource& source);

// The provenance an earlier session wrote into a file of the run (a checkpoint or a shard): the
// ensemble's kind, seed and description, the configuration as given, the first command line
// and when it started.
void read_provenance(const h5::Group& root, Run& r);

// Refuses (io) a file of the run (a checkpoint, a shard) whose own attributes contradict the run
// `r` describes (from the file's configuration and provenance): its schema, map, parameters,
// steps, stride, start rule, escape bound, ensemble kind and seed. A file altered, or pieced
// together from two runs, is so refused before it is read.
void check_record_of(const h5::Group& root, const Run& r);

// Refuses (usage) an output name that cannot be a file's: empty, with a NUL byte, or naming a
// folder (ending in '/', '.' or '..'); `where` names its key or option.
void check_output_name(const std::string& path, const std::string& where);

// The memory the run holds: its ensemble (padded), its observers with each thread's partial, its
// trajectories.
double memory_of(const Run& r);
// The same for a run of the same keys and map with `orbits` orbits instead (a sweep's other
// points, known before their observers are made): a section's slots scale with the orbits.
double memory_of(const Run& r, std::size_t orbits);

// The record of the run with the ensemble where it is now, this session ended at `now`; its
// observers are the run's (a checkpoint restores them, a merge adds to them).
RunRecord record_of(Run& r, const Ensemble& e, long long session_first,
                    const std::string& session_started, const std::string& now,
                    const std::string& session_command);

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
    const std::string what = failure.what(), reason = err ? std::strerror(err) : "";
    const bool named = reason.empty() || what.find(reason) != std::string::npos;
    throw Error(ExitCode::io, "cannot write '" + path + "': " + what +
                                  (named ? std::string() : " (" + reason + ")"));
  }
}


}  // namespace qmaps
