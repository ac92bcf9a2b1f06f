#pragma once
// The model a configuration's [map] names: `name` and the map's parameters, with the chaos record
// `chaos` asks for (docs/chaos.md). Its errors say where in the configuration the map is.
#include <memory>
#include <optional>

#include "core/model.hpp"
#include "ensembles/config/config.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {

std::unique_ptr<Model> map_of(const Config& config,
                              const std::optional<ChaosOptions>& chaos = std::nullopt);

}  // namespace qmaps
