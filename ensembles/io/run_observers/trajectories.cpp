// /trajectories/<name> (docs/hdf5-schema.md): each trajectory's rows, orbit by orbit in its
// configured order, and its `every` (core/observers/trajectory/trajectory.hpp); recorded when the
// run starts (ensembles/io/trajectories.hpp).
#include "ensembles/io/run_observers/run_observers.hpp"

namespace qmaps {

void describe_trajectories(const RunRecord& run, MeasuredOutput& out) {
  if (!run.trajectories) return;
  for (Trajectory& t : *run.trajectories) {
    const std::string group = "trajectories/" + t.name;
    out.attribute(group, "every", static_cast<std::int64_t>(t.every));
    out.series.push_back({group, &t, run.plan.total});
  }
}

}  // namespace qmaps
