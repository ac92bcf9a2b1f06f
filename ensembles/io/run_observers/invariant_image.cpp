// /invariants/image (docs/hdf5-schema.md): the histogram of the orbits' initial invariants over
// the two the configuration names (core/observers/invariants/invariant_image.hpp).
#include "core/observers/invariants/invariant_columns.hpp"
#include "ensembles/io/run_observers/run_observers.hpp"

namespace qmaps {

void describe_invariant_image(const RunRecord& run, MeasuredOutput& out) {
  if (!run.image) return;
  Histogram& image = out.hold(run.image->histogram);
  const auto& names = run.model.invariant_names();
  std::size_t ix = 0, iy = 0;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (names[k] == image.axes()[0].coordinate) ix = k;
    if (names[k] == image.axes()[1].coordinate) iy = k;
  }
  const Ensemble& e = run.ensemble;
  for (std::size_t i = 0; i < e.orbits; ++i) {
    const double v[2] = {invariant_initial(e, ix)[i], invariant_initial(e, iy)[i]};
    image.add(v);
  }
  out.histograms.push_back({"invariants/image", "counts", &image, false});
}

}  // namespace qmaps
