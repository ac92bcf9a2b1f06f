#include "ensembles/kinds/initial_conditions.hpp"

#include <omp.h>

#include <limits>

#include "core/error.hpp"
#include "ensembles/kinds/box.hpp"
#include "ensembles/kinds/from_file.hpp"
#include "ensembles/kinds/grid.hpp"
#include "ensembles/kinds/line.hpp"
#include "ensembles/kinds/shell.hpp"

namespace qmaps {

std::uint64_t generate(const EnsembleKind& kind, std::size_t first, std::span<Phase> out,
                       int threads, std::size_t chunk) {
  std::uint64_t rejected = 0;
  std::size_t failed = std::numeric_limits<std::size_t>::max();
  const long long count = static_cast<long long>(out.size());
  const int team = threads > 0 ? threads : omp_get_max_threads();
  const int step = static_cast<int>(chunk > 0 ? chunk : 1);
#pragma omp parallel for schedule(dynamic, step) num_threads(team) reduction(+ : rejected)
  for (long long j = 0; j < count; ++j) {
    const std::size_t i = first + static_cast<std::size_t>(j);
    try {
      const Drawn d = kind.draw(i);
      out[static_cast<std::size_t>(j)] = d.point;
      rejected += d.rejected;
    } catch (const std::exception&) {  // rethrown below, outside the parallel region
#pragma omp critical(qmaps_generate_failed)
      failed = std::min(failed, i);
    }
  }
  if (failed != std::numeric_limits<std::size_t>::max()) kind.draw(failed);  // throws its error
  return rejected;
}

Generated generate(const EnsembleKind& kind, int threads, std::size_t chunk) {
  Generated g;
  g.points.resize(kind.orbits());
  g.rejected = generate(kind, 0, g.points, threads, chunk) + kind.rejected_up_front();
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

std::uint64_t InitialConditions::start(const Model& model, Ensemble& e, Start rule,
                                       double escape_bound, const PointsSink& sink,
                                       std::size_t part) const {
  const auto* file = dynamic_cast<const FromFile*>(generator_.get());
  const bool continues = file && file->continues();
  if (continues) file->continue_into(e, escape_bound);
  std::uint64_t rejected = generator_->rejected_up_front();
  const std::size_t n = orbits();
  std::vector<Phase> points(std::min(n, part));
  for (std::size_t first = 0; first < n; first += part) {
    const auto some = std::span<Phase>(points).first(std::min(part, n - first));
    rejected += generate(*generator_, first, some);
    sink(first, some);
    if (!continues) model.start_at(e, first, some, rule, escape_bound);
  }
  e.fill_padding();
  return rejected;
}

}  // namespace qmaps
