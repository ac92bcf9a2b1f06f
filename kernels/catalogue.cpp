#include "kernels/catalogue.hpp"

#include <array>
#include <vector>
#include <string>

#include "core/error.hpp"
#include "core/model_units.hpp"  // the models, each compiled in its own unit

namespace qmaps {
namespace {

template <KernelMap Map>
MapEntry entry() {
  return {Map::name, Map::summary, Map::equations, Map::invariant_summary, Map::params,
          &Map::facts,
          [](const ParamValues& p) -> std::unique_ptr<Model> {
            return std::make_unique<ModelOf<Map>>(p);
          },
          [](const ParamValues& p, const ChaosOptions& chaos) -> std::unique_ptr<Model> {
            if (chaos.spectrum) return std::make_unique<ModelOf<Tangent<Map, 9>>>(p, chaos.every);
            return std::make_unique<ModelOf<Tangent<Map, 1>>>(p, chaos.every);
          }};
}

// Built on first use (other translation units' static initializers may ask for it).
const auto& maps() {
  static const auto list = [] {
    std::vector<MapEntry> out;
    kernels::for_each_map([&](auto map) { out.push_back(entry<decltype(map)>()); });
    return out;
  }();
  return list;
}

}  // namespace

std::span<const MapEntry> catalogue() { return maps(); }

static const MapEntry& entry_named(std::string_view name) {
  for (const auto& m : maps())
    if (m.name == name) return m;
  std::string known;
  for (const auto& m : maps()) known += (known.empty() ? "" : ", ") + std::string(m.name);
  throw usage_error("unknown map '" + std::string(name) + "' (known maps: " + known + ")");
}

std::unique_ptr<Model> make_model(std::string_view name, const ParamValues& params) {
  return entry_named(name).make(params);
}
std::unique_ptr<Model> continuous_model(const Model& model) {
  const auto continuous = model.continuous();
  if (!continuous) return nullptr;
  const Potential v = *continuous;
  return std::make_unique<ModelOf<kernels::Flow>>(ParamValues{
      {"A", v.A}, {"B", v.B}, {"alpha", v.alpha}, {"beta", v.beta}, {"delta", v.delta},
      {"h", 1.0}});
}

std::unique_ptr<Model> make_model(std::string_view name, const ParamValues& params,
                                  const ChaosOptions& chaos) {
  return entry_named(name).make_chaos(params, chaos);
}

std::unique_ptr<Model> make_model(const std::shared_ptr<const formula::Definition>& definition,
                                  const ParamValues& params) {
  return std::make_unique<ModelOf<kernels::Formula>>(params, definition);
}
std::unique_ptr<Model> make_model(const std::shared_ptr<const formula::Definition>& definition,
                                  const ParamValues& params, const ChaosOptions& chaos) {
  using kernels::Formula;
  if (chaos.spectrum)
    return std::make_unique<ModelOf<Tangent<Formula, 9>>>(params, chaos.every, definition);
  return std::make_unique<ModelOf<Tangent<Formula, 1>>>(params, chaos.every, definition);
}

}  // namespace qmaps
