#include "ensembles/config/map_config.hpp"

#include "core/error.hpp"

namespace qmaps {

std::unique_ptr<Model> map_of(const Config& config, const std::optional<ChaosOptions>& chaos) {
  const std::string name = config.string("map", "name");
  ParamValues params;
  for (const auto& key : config.keys("map"))
    if (key != "name") params[key] = config.number("map", key);
  try {
    return chaos ? make_model(name, params, *chaos) : make_model(name, params);
  } catch (const Error& e) {
    throw Error(e.code(), config.where("map") + ": " + e.what());
  }
}

}  // namespace qmaps
