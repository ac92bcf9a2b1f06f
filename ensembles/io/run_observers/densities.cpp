// /histograms/<name> (docs/hdf5-schema.md): each density's counts over every rank, and the
// stride it was sampled at (core/observers/density/density.hpp).
#include "ensembles/io/run_observers/run_observers.hpp"

namespace qmaps {

void describe_densities(const RunRecord& run, MeasuredOutput& out) {
  if (!run.observers) return;
  for (Density& d : run.observers->densities) {
    const std::string group = "histograms/" + d.histogram.name();
    out.histograms.push_back({group, "counts", &d.histogram, true});
    out.attribute(group, "stride", static_cast<std::int64_t>(run.plan.stride));
  }
}

}  // namespace qmaps
