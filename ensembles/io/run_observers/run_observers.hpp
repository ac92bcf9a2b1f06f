#pragma once
// Every run observer: what it leaves in a run's file, described from the run once
// (ensembles/io/measured_output.hpp); the file's writer, the checkpoint and qmaps merge iterate
// this list and name none of them. The lane measurements, which the block drives while it
// steps, are listed in core/observers/lane_observers.hpp.
//
// An observer is a function describe_<name>(run, out) in a file of this folder and one entry
// below, in the order of the file. `kept`: its output is the run's state (accumulated while the
// run steps, or recorded when it starts), so a checkpoint keeps it and a merge adds the
// shards'; the others are computed from the orbits whenever a file is written.
#include "ensembles/io/measured_output.hpp"
#include "ensembles/io/output.hpp"

namespace qmaps {

using Describe = void (*)(const RunRecord& run, MeasuredOutput& out);
void describe_drift_histograms(const RunRecord& run, MeasuredOutput& out);
void describe_invariant_image(const RunRecord& run, MeasuredOutput& out);
void describe_densities(const RunRecord& run, MeasuredOutput& out);
void describe_sections(const RunRecord& run, MeasuredOutput& out);
void describe_chaos(const RunRecord& run, MeasuredOutput& out);
void describe_tunes(const RunRecord& run, MeasuredOutput& out);
void describe_trajectories(const RunRecord& run, MeasuredOutput& out);

struct RunObserver {
  Describe describe;
  bool kept;
};
inline constexpr RunObserver run_observers[] = {
    {describe_drift_histograms, false},
    {describe_invariant_image, false},
    {describe_densities, true},
    {describe_sections, true},
    {describe_chaos, false},
    {describe_tunes, false},
    {describe_trajectories, true},
};

// The output of every observer of the run; of the kept ones alone.
MeasuredOutput describe_run(const RunRecord& run);
MeasuredOutput describe_kept(const RunRecord& run);

}  // namespace qmaps
