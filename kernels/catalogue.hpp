#pragma once
// Every map of kernels/maps.hpp, by the name that `--map` and `[map] name` take.
#include <memory>
#include <span>
#include <string_view>

#include "core/map_concept.hpp"
#include "core/model.hpp"
#include "kernels/formula/definition.hpp"

namespace qmaps {

struct MapEntry {
  std::string_view name;
  std::string_view summary;
  std::string_view equations;          // the paper's equation labels it implements
  std::string_view invariant_summary;  // its invariants, e.g. "H, I1, I2 (A != B); H, L (A = B)"
  std::span<const ParamSpec> params;
  const MapFacts* facts;  // its example parameters, tolerances and preset
  std::unique_ptr<Model> (*make)(const ParamValues&);
  std::unique_ptr<Model> (*make_chaos)(const ParamValues&, const struct ChaosOptions&);
};

// What a run's [chaos] records (core/tangent_map.hpp): λ, FLI and MEGNO from one deviation, or
// also the spectrum and GALI_2, GALI_4 from nine; the spectrum orthonormalized every `every` steps.
struct ChaosOptions {
  bool spectrum = false;
  long long every = 10;
};

std::span<const MapEntry> catalogue();

// The model of map `name` with these parameters; an unknown name is a usage error listing the maps.
std::unique_ptr<Model> make_model(std::string_view name, const ParamValues& params);
// The continuous system `model` discretizes, as the flow (kernels/flow.hpp) of its potential:
// its invariants are the continuous H and the case's second integral ("H_cont" beside the map's);
// null for a formula map that names none.
std::unique_ptr<Model> continuous_model(const Model& model);
// The same map advancing its chaos record with its state.
std::unique_ptr<Model> make_model(std::string_view name, const ParamValues& params,
                                  const ChaosOptions& chaos);

// The model of a map written as formulas (kernels/formula/definition.hpp), alone or with its chaos
// record.
std::unique_ptr<Model> make_model(const std::shared_ptr<const formula::Definition>& definition,
                                  const ParamValues& params);
std::unique_ptr<Model> make_model(const std::shared_ptr<const formula::Definition>& definition,
                                  const ParamValues& params, const ChaosOptions& chaos);

}  // namespace qmaps
