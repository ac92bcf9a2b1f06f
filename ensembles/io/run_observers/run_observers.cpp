#include "ensembles/io/run_observers/run_observers.hpp"

namespace qmaps {

MeasuredOutput describe_run(const RunRecord& run) {
  MeasuredOutput out;
  for (const RunObserver& o : run_observers) o.describe(run, out);
  return out;
}

MeasuredOutput describe_kept(const RunRecord& run) {
  MeasuredOutput out;
  for (const RunObserver& o : run_observers)
    if (o.kept) o.describe(run, out);
  return out;
}

}  // namespace qmaps
