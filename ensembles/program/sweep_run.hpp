#pragma once
// qmaps run of a configuration with [[sweep]] (docs/sweeps.md): every point's run is set up and
// checked before any runs (a map that degenerates at a point is refused then), all points step
// together (core/runner.hpp), and one file holds /sweep with each point's run.
#include <iosfwd>
#include <string>

#include "ensembles/config/config.hpp"
#include "ensembles/config/sweep_config.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"

namespace qmaps {

int run_sweep(const Config& config, const Sweep& sweep, const RunOptions& options,
              const std::string& started, const InterruptGuard& interrupt, std::ostream& log);

}  // namespace qmaps
