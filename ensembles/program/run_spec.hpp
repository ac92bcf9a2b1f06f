#pragma once
// A new run as its configuration describes it, read once and checked in one place: the
// configuration with its overrides, the map with its chaos record, and either a sweep or the
// ensemble's initial conditions and the run (plan, path, execution, lane measurements,
// observers, output). Every key is read here, and one that no reader asked for is refused here,
// with its line. qmaps run, qmaps-mpi and the Python module read a spec, then run its session
// (run_spec, in run_command.cpp); a checkpoint's run, and shards', from the configuration their
// files record (read_recorded_spec).
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "ensembles/config/config.hpp"
#include "ensembles/config/sweep_config.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/run_setup.hpp"

namespace qmaps {

// One run of a spec: its orbits' starting points (none for a run already begun: its file holds
// them) and the run itself.
struct RunPoint {
  std::optional<InitialConditions> initial;
  Run run;
};

struct RunSpec {
  Config config;
  std::string started;           // when it was read, ISO 8601 UTC
  std::optional<Sweep> sweep;    // a sweep, whose points are the runs below, in its order
  std::vector<RunPoint> points;  // a run: one
  bool ran = false;              // a spec runs once: its observers fill
};

// The spec of the run its source describes: the configuration (its file, or its text), --set,
// --out, --shard and an in-process caller's points; --threads and --simd choose its path. Over
// the ranks of qmaps-mpi every rank reads it, and all fail alike.
RunSpec read_spec(const SpecSource& source);

// The spec of a run already begun (a checkpoint's, or the shards' that qmaps merge joins), from
// the configuration its file records (`where` names it in messages): its run of `orbits` orbits
// on the path `source` asks, whose shard, if any, it names. Its initial conditions are not made
// again, so the keys of its ensemble are not read.
RunSpec read_recorded_spec(const std::string& config_resolved, const std::string& where,
                           std::size_t orbits, const SpecSource& source);

// Runs it: a sweep's points, or the run's segments, checkpoints and file, as the session asks
// (progress, quiet, what a signal leaves, the command line recorded).
int run_spec(RunSpec& spec, const SessionOptions& session, const InterruptGuard& interrupt,
             std::ostream& log);

}  // namespace qmaps
