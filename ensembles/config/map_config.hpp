#pragma once
// The model a configuration's [map] names: `name` and the map's parameters, with the chaos record
// `chaos` asks for (docs/chaos.md); or a map written as formulas (docs/formulas.md: `form` and
// its formulas' keys, the other keys its parameters' values). Its errors say where in the
// configuration the map is, and a formula's error its key, line and column.
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

// Whether [map] is written as formulas (it has a `form`), and their definition.
bool is_formula_map(const Config& config);
std::shared_ptr<const formula::Definition> definition_of(const Config& config);

std::unique_ptr<Model> map_of(const Config& config,
                              const std::optional<ChaosOptions>& chaos = std::nullopt);

// [map]'s parameter values: every key but the formula keys (of a built-in map: but its name).
ParamValues map_params(const Config& config);
// Whether `--map` names a file (*.toml) rather than a built-in map.
bool names_file(const std::string& map);
// The configuration of the file `--map` names, whose [map] must be written as formulas, with
// `params` set in its [map].
Config formula_map_file(const std::string& map, const ParamValues& params);

// The model `--map` names: a built-in map's name, or a configuration file (*.toml) whose [map]
// is written as formulas; `params` replace its values.
std::unique_ptr<Model> map_named(const std::string& map, const ParamValues& params,
                                 const std::optional<ChaosOptions>& chaos = std::nullopt);

}  // namespace qmaps
