#include "ensembles/initial_conditions.hpp"

#include <omp.h>

#include <limits>

#include "core/error.hpp"
#include "ensembles/box.hpp"
#include "ensembles/from_file.hpp"
#include "ensembles/grid.hpp"
#include "ensembles/line.hpp"
#include "ensembles/shell.hpp"

namespace qmaps {

Generated generate(const EnsembleKind& kind, int threads, std::size_t chunk) {
  const std::size_t n = kind.orbits();
  Generated g;
  g.points.resize(n);
  std::uint64_t rejected = 0;
  std::size_t failed = std::numeric_limits<std::size_t>::max();
  const long long count = static_cast<long long>(n);
  const int team = threads > 0 ? threads : omp_get_max_threads();
  const int step = static_cast<int>(chunk > 0 ? chunk : 1);
#pragma omp parallel for schedule(dynamic, step) num_threads(team) reduction(+ : rejected)
  for (long long i = 0; i < count; ++i) {
    try {
      const Drawn d = kind.draw(static_cast<std::size_t>(i));
      g.points[static_cast<std::size_t>(i)] = d.point;
      rejected += d.rejected;
    } catch (const std::exception&) {  // rethrown below, outside the parallel region
#pragma omp critical(qmaps_generate_failed)
      failed = std::min(failed, static_cast<std::size_t>(i));
    }
  }
  if (failed != std::numeric_limits<std::size_t>::max()) kind.draw(failed);  // throws its error
  g.rejected = rejected + kind.rejected_up_front();
  return g;
}

InitialConditions InitialConditions::from_config(const Config& config, const Model& model) {
  InitialConditions ic;
  ic.kind_ = config.string_or("ensemble", "kind", "box");
  if (ic.kind_ == "box")
    ic.generator_ = std::make_shared<Box>(config);
  else if (ic.kind_ == "grid")
    ic.generator_ = std::make_shared<Grid>(config);
  else if (ic.kind_ == "shell")
    ic.generator_ = std::make_shared<Shell>(config, model.continuous());
  else if (ic.kind_ == "line")
    ic.generator_ = std::make_shared<Line>(config);
  else if (ic.kind_ == "file")
    ic.generator_ = std::make_shared<FromFile>(config, model);
  else
    throw usage_error(config.where("ensemble", "kind") + ": unknown ensemble kind '" + ic.kind_ +
                      "' (known: " + kinds + ")");
  return ic;
}

Started InitialConditions::start(const Model& model, Start rule, double escape_bound,
                                 int threads) const {
  Generated g = generate(*generator_, threads);
  if (const auto* file = dynamic_cast<const FromFile*>(generator_.get()))
    if (auto e = file->continued(escape_bound))
      return {std::move(*e), std::move(g.points), g.rejected};
  Ensemble e = model.start(g.points, rule, escape_bound);
  return {std::move(e), std::move(g.points), g.rejected};
}

}  // namespace qmaps
