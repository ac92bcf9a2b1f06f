#pragma once
// qmaps run of a configuration with [[sweep]] (docs/sweeps.md): every point's run is set up and
// checked before any runs (run_spec.hpp: a map that degenerates at a point is refused then), all points step
// together (core/runner.hpp), and one file holds /sweep with each point's run.
#include <iosfwd>
#include <string>

#include "ensembles/config/config.hpp"
#include "ensembles/config/sweep_config.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/run_spec.hpp"

namespace qmaps {

// The sweep of `spec` (read_spec: every point's run set up and checked).
int run_sweep(RunSpec& spec, const SessionOptions& session, const InterruptGuard& interrupt,
              std::ostream& log);

}  // namespace qmaps
