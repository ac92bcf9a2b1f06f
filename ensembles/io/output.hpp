#pragma once
// The HDF5 file of a run (docs/hdf5-schema.md): provenance, initial and final phase points, the
// final state, invariants and escapes.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/ensemble.hpp"
#include "ensembles/io/h5.hpp"
#include "core/model.hpp"
#include "core/observers/invariants/invariant_image.hpp"
#include "core/observers/observers.hpp"
#include "core/run_plan.hpp"
#include "ensembles/io/trajectories.hpp"

namespace qmaps {

inline constexpr std::int64_t schema_version = 1;

// Refuses (io) a file of another schema than this qmaps writes: a newer one is never read as if
// it were this one.
void check_schema(const h5::Group& root, const std::string& path);

// How /chaos reports the indicators (docs/chaos.md): an orbit is chaotic where its MEGNO ⟨Y⟩
// exceeds the threshold; each indicator's histogram has `bins` bins over its range.
struct ChaosReport {
  double megno_threshold = 3;
  long long bins = 100;
};

// How /tunes reports the tunes (docs/tunes.md): an orbit is chaotic where its diffusion exceeds
// the threshold; the histograms have `bins` bins, the frequency map bins × bins.
struct TuneReport {
  double diffusion_threshold = -6;
  long long bins = 100;
};

// The rows of a file's per-orbit datasets that this process writes: [first, first + count) of
// total. A rank of qmaps-mpi writes its orbits' rows into the one file of the run; any other
// process writes all of them (first 0, count = total).
struct Rows {
  std::size_t first = 0, count = 0, total = 0;

  // These rows, or all n when none are given (count 0: a process alone).
  Rows or_all(std::size_t n) const { return count > 0 ? *this : Rows{0, n, n}; }
};

// The histogram's counts, underflow and overflow added over every rank (ensembles/io/ranks.hpp).
void add_over_ranks(Histogram& h);

// Everything of a run but /initial, which is written first, by parts (create_phase, write_phase_part),
// as the orbits start. On a shared file (qmaps-mpi) every rank writes it together: each its own
// rows, and the rest as rank 0 has it.
struct RunRecord {
  const Model& model;
  const Ensemble& ensemble;
  RunPlan plan;
  Execution execution;  // of the last session
  std::string ensemble_kind;
  std::uint64_t seed = 0;
  Start start = Start::taylor;
  bool per_orbit = true;  // [output] per_orbit: false leaves out every dataset of shape (N_o,)
  std::string config_text{}, config_resolved{}, command_line{};
  std::string started{}, finished{};  // ISO 8601, UTC
  std::string sessions{};         // one line per process that advanced the run (session_line)
  Observers* observers = nullptr;  // accumulated: a checkpoint restores them, a merge adds to them
  const InvariantImage* image = nullptr;
  std::string ensemble_description{};  // what the initial conditions are, in one line
  std::uint64_t rejected = 0;        // candidates rejected (shell ensembles)
  ChaosReport chaos{};
  TuneReport tunes{};
  std::vector<Trajectory>* trajectories = nullptr;
  // A shard's file (docs/cli.md): "k/K", and its orbits' place in the ensemble of orbits_total.
  std::string shard{};
  std::int64_t shard_first = 0, orbits_total = 0;
  Rows rows{};  // the ensemble's rows of the file; count 0: the ensemble is the file's
};

// One session of a run: its steps, path, ranks and threads, times and command line.
std::string session_line(long long first, long long last, const Execution& x,
                         const std::string& started, const std::string& finished,
                         const std::string& command_line);

// Per-orbit datasets are written and copied this many orbits at a time: a column's part (512 KiB)
// stays in cache and its buffer is reused (10^6 orbits written at 1.09 GB/s, against 0.51 GB/s
// in parts of 2^20 orbits, whose fresh buffers cost page faults).
inline constexpr std::size_t orbits_per_part = std::size_t{1} << 16;

// The datasets q1, q2, p1, p2 of `g` for n orbits, written by parts.
void create_phase(const h5::Group& g, std::size_t n);
void write_phase_part(const h5::Group& g, std::size_t first, std::span<const Phase> points);
// Reads points [first, first + points.size()) of a file's phase group, each of its datasets
// exactly `total` long: another length, or a point that is not finite, is an io error.
void read_phase_part(const h5::Group& g, std::size_t first, std::size_t total,
                     std::span<Phase> points);
// The parts of `count` rows, orbits_per_part at a time: as many on every rank (the most any rank
// has), so that the collective writes of a shared file pair up; past its rows a rank's are empty.
std::size_t parts_of(std::size_t count);
// The dataset `name` of rows.total elements (T: double, std::int64_t or std::uint8_t): this
// process's rows [rows.first, rows.first + rows.count) from `values`, by parts.
template <class T>
void write_rows(const h5::Group& g, const std::string& name, std::span<const T> values, Rows rows);
// Copies the phase datasets of `from` into new ones of `to`, both of rows.total orbits: rows
// [rows.first, rows.first + rows.count), by parts.
void copy_phase(const h5::Group& from, const h5::Group& to, Rows rows);

// The dataset at `path` from `root`, in a group ("invariants/H/initial"): the group that holds it,
// made where missing when `make`, and its name there.
struct DatasetAt {
  h5::Group group;
  std::string name;
};
DatasetAt dataset_at(const h5::Group& root, const std::string& path, bool make = false);

// The schema and the build that wrote the file: version, commit, compiler and flags.
void write_build(const h5::Group& root);
void write_run(const h5::Group& root, const RunRecord& run);

// The current time as ISO 8601 UTC, e.g. 2026-11-21T12:00:00Z.
std::string utc_now();

}  // namespace qmaps
