#pragma once
// /sweep of a sweep's file (docs/hdf5-schema.md): the axes, every point's parameters and summary
// (orbits, escapes, the worst invariant drift and, with [chaos], the chaotic fraction and median
// indicators), and each point's run in /sweep/runs/<k>, laid out as a run's own file.
#include <span>
#include <vector>

#include "ensembles/io/h5.hpp"
#include "ensembles/config/sweep_config.hpp"
#include "ensembles/io/output.hpp"

namespace qmaps {

// /sweep/runs/<k> for each point, made before the points start (their /initial is written then).
std::vector<h5::Group> create_sweep_runs(const h5::Group& root, std::size_t points);

// The file's provenance, /sweep's axes and summaries, and point k's run (runs[k]) into
// /sweep/runs/<k>.
void write_sweep(const h5::Group& root, const Sweep& sweep, std::span<const RunRecord> runs);

}  // namespace qmaps
