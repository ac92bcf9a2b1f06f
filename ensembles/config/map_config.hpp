#pragma once
// The model a configuration's [map] names: `name` and the map's parameters, with the chaos record
// `chaos` asks for (docs/chaos.md). Its errors say where in the configuration the map is.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "ensembles/config/config.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {

// The number that is the whole of `text`, if it is one: a subnormal stays one, a number beyond
// the largest double reads as ±inf (each parameter's own rule then says why it is refused).
std::optional<double> number_in(const std::string& text);
// Map parameters from "name=value" items (--set of `orbit` and `check`).
ParamValues parse_params(const std::vector<std::string>& sets);

std::unique_ptr<Model> map_of(const Config& config,
                              const std::optional<ChaosOptions>& chaos = std::nullopt);

}  // namespace qmaps
