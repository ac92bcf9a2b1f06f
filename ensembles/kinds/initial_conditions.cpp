#include "ensembles/kinds/initial_conditions.hpp"

#include <omp.h>

#include <limits>
#include <string_view>
#include <type_traits>
#include <utility>

#include "core/error.hpp"
#include "ensembles/kinds/box.hpp"
#include "ensembles/kinds/from_file.hpp"
#include "ensembles/kinds/given_points.hpp"
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

namespace {

// The continuous system by whose energy a kind places its orbits.
Potential continuous_of(const Config& config, const Model& model) {
  const auto continuous = model.continuous();
  if (!continuous)
    throw usage_error(config.where("ensemble", "kind") + ": '" +
                      config.string("ensemble", "kind") + "' places orbits by the energy of the "
                      "continuous Hamiltonian, and map '" + std::string(model.name()) +
                      "' names none (a formula map's [map] continuous)");
  return *continuous;
}

// Every ensemble kind, by the name [ensemble] kind takes.
struct KindEntry {
  std::string_view name;
  std::shared_ptr<const EnsembleKind> (*make)(const Config&, const Model&, const StopCheck&);
};
template <class Kind>
std::shared_ptr<const EnsembleKind> make_kind(const Config& config, const Model& model,
                                              const StopCheck& stop) {
  if constexpr (std::is_constructible_v<Kind, const Config&, Potential, StopCheck>)
    return std::make_shared<Kind>(config, continuous_of(config, model), stop);
  else if constexpr (std::is_constructible_v<Kind, const Config&, const Model&>)
    return std::make_shared<Kind>(config, model);
  else if constexpr (std::is_constructible_v<Kind, const Config&, Potential>)
    return std::make_shared<Kind>(config, continuous_of(config, model));
  else
    return std::make_shared<Kind>(config);
}
constexpr KindEntry kinds_list[] = {{"box", make_kind<Box>},     {"grid", make_kind<Grid>},
                                    {"shell", make_kind<Shell>}, {"line", make_kind<Line>},
                                    {"file", make_kind<FromFile>}};

}  // namespace

std::string InitialConditions::kinds() {
  std::string names;
  for (const auto& k : kinds_list) names += (names.empty() ? "" : ", ") + std::string(k.name);
  return names;
}

InitialConditions InitialConditions::from_config(const Config& config, const Model& model,
                                                 StopCheck stop) {
  InitialConditions ic;
  ic.stop_ = std::move(stop);
  ic.kind_ = config.string_or("ensemble", "kind", "box");
  for (const auto& k : kinds_list)
    if (k.name == ic.kind_) ic.generator_ = k.make(config, model, ic.stop_);
  if (!ic.generator_)
    throw usage_error(config.where("ensemble", "kind") + ": unknown ensemble kind '" + ic.kind_ +
                      "' (known: " + kinds() + ")");
  return ic;
}

InitialConditions InitialConditions::of_points(const Config& config,
                                               std::shared_ptr<const std::vector<Phase>> points) {
  if (config.has_section("ensemble"))
    throw usage_error(config.where("ensemble") +
                      ": the initial conditions are given as points; leave out [ensemble]");
  InitialConditions ic;
  ic.kind_ = "points";
  ic.generator_ = std::make_shared<GivenPoints>(std::move(points));
  return ic;
}

std::uint64_t InitialConditions::start(const Model& model, Ensemble& e, Start rule,
                                       double escape_bound, const PointsSink& sink,
                                       std::size_t part, std::size_t offset) const {
  if (offset + e.orbits > orbits())
    throw usage_error("orbits [" + std::to_string(offset) + ", " + std::to_string(offset + e.orbits) +
                      ") are not in the ensemble of " + std::to_string(orbits()));
  const bool continues = generator_->continues();
  if (continues) generator_->continue_into(e, offset, escape_bound);
  // The candidates rejected once for all count with the ensemble's first orbit.
  std::uint64_t rejected = offset == 0 ? generator_->rejected_up_front() : 0;
  const std::size_t n = e.orbits;
  std::vector<Phase> points(std::min(n, part));
  for (std::size_t first = 0; first < n; first += part) {
    check_stop(stop_, "drawing the initial conditions");
    const auto some = std::span<Phase>(points).first(std::min(part, n - first));
    rejected += generate(*generator_, offset + first, some);
    sink(first, some);
    if (!continues) model.start_at(e, first, some, rule, escape_bound);
  }
  e.fill_padding();
  return rejected;
}

}  // namespace qmaps
