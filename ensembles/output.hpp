#pragma once
// The HDF5 file of a run (docs/hdf5-schema.md): provenance, initial and final phase points, the
// final state, invariants and escapes.
#include <cstdint>
#include <span>
#include <string>

#include "core/ensemble.hpp"
#include "core/h5.hpp"
#include "core/model.hpp"
#include "core/observers.hpp"
#include "core/run_plan.hpp"
#include "ensembles/observer_config.hpp"

namespace qmaps {

inline constexpr std::int64_t schema_version = 1;

struct RunRecord {
  const Model& model;
  const Ensemble& ensemble;
  std::span<const Phase> initial;
  RunPlan plan;
  Execution execution;
  std::string ensemble_kind;
  std::uint64_t seed = 0;
  Start start = Start::taylor;
  std::string config_text, config_resolved, command_line;
  std::string started, finished;  // ISO 8601, UTC
  const Observers* observers = nullptr;
  const InvariantImage* image = nullptr;
  std::string ensemble_description;  // what the initial conditions are, in one line
  std::uint64_t rejected = 0;        // candidates rejected (shell ensembles)
};

// The histogram of log10 of each orbit's max relative drift max|I_n − I_0|/|I_0| of invariant k:
// bins of 0.25 from −18 to 0; `zero` counts drifts exactly 0 (kept apart from the bins).
struct DriftHistogram {
  Histogram histogram;
  std::int64_t zero = 0;
};
DriftHistogram drift_histogram(const Ensemble& e, std::size_t invariant);

void write_run(const h5::Group& root, const RunRecord& run);

// The current time as ISO 8601 UTC, e.g. 2026-11-21T12:00:00Z.
std::string utc_now();

}  // namespace qmaps
