// /invariants/<I>/drift_histogram (docs/hdf5-schema.md): the histogram of log10 of each orbit's
// relative drift of invariant I (ensembles/io/statistics.hpp), in bins of 0.25 from −18 to 0;
// `zero` counts the drifts exactly 0, kept apart from the bins.
#include <cmath>

#include "core/observers/invariants/invariant_columns.hpp"
#include "ensembles/io/run_observers/run_observers.hpp"
#include "ensembles/io/statistics.hpp"

namespace qmaps {

void describe_drift_histograms(const RunRecord& run, MeasuredOutput& out) {
  const Ensemble& e = run.ensemble;
  const auto& names = run.model.invariant_names();
  for (std::size_t k = 0; k < names.size(); ++k) {
    Histogram& h = out.hold(Histogram("log10_relative_drift", {{"log10_relative_drift", -18.0, 0.0, 72}}));
    std::int64_t zero = 0;
    const auto& initial = invariant_initial(e, k);
    const auto& drift = invariant_drift(e, k);
    for (std::size_t i = 0; i < e.orbits; ++i) {
      if (drift[i] == 0) {
        ++zero;
        continue;
      }
      const double x = std::log10(relative_drift(initial[i], drift[i]));
      h.add(&x);
    }
    const std::string group = "invariants/" + names[k] + "/drift_histogram";
    out.histograms.push_back({group, "counts", &h, false});
    out.attribute(group, "zero", zero, MeasuredOutput::Over::summed);
  }
}

}  // namespace qmaps
