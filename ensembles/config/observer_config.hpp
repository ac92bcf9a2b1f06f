#pragma once
// The observers of a run from its configuration: [[histogram]], [[section]], [invariant_image]
// and [[trajectory]] (docs/cli.md; annotated in docs/getting-started.md); every error names the
// key and its line.
#include <optional>
#include <string>

#include "ensembles/config/config.hpp"
#include "core/observers/histogram.hpp"
#include "core/model.hpp"
#include "core/observers/invariants/invariant_image.hpp"
#include "core/observers/observers.hpp"
#include "core/observers/trajectory/trajectory.hpp"
#include "core/run_plan.hpp"
#include "ensembles/io/output.hpp"

namespace qmaps {

// [tunes] (docs/tunes.md), for a run of `steps` steps: the windows the runner records and
// analyses (none without the table) and how /tunes reports them.
struct TuneSettings {
  TuneWindows windows;
  TuneReport report;
};
TuneSettings tunes_from_config(const Config& config, long long steps);

// `steps`: the run's, which bound the points a section's orbit can keep.
Observers observers_from_config(const Config& config, const Model& model, std::size_t orbits,
                                long long steps);
std::optional<InvariantImage> invariant_image_from_config(const Config& config, const Model& model);
// [[trajectory]]: which orbits, every how many steps (their rows are recorded later).
std::vector<Trajectory> trajectories_from_config(const Config& config, const Model& model,
                                                 std::size_t orbits, long long steps);

}  // namespace qmaps
