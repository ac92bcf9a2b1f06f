#include "ensembles/config/map_config.hpp"

#include <algorithm>
#include <cstdlib>

#include "core/error.hpp"

namespace qmaps {

std::optional<double> number_in(const std::string& text) {
  // strtod, not stod: a number beyond the range of a double (a subnormal such as 1e-320, or
  // 1e400 read as inf) is still a number, for the parameter's own rule to judge.
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return std::nullopt;
  return value;
}

ParamValues parse_params(const std::vector<std::string>& sets) {
  ParamValues params;
  for (const auto& s : sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw usage_error("--set expects name=value, got '" + s + "'");
    const std::string name = s.substr(0, eq), text = s.substr(eq + 1);
    const auto value = number_in(text);
    if (!value) throw usage_error("--set " + name + ": '" + text + "' is not a number");
    params[name] = *value;
  }
  return params;
}


bool is_formula_map(const Config& config) { return config.has("map", "form"); }

std::shared_ptr<const formula::Definition> definition_of(const Config& config) {
  formula::MapText text;
  for (const std::string_view key : formula::map_keys)
    formula::text_of(text, key) = config.string_or("map", key, "");
  try {
    return formula::Definition::parse(text);
  } catch (const formula::DefinitionError& e) {
    throw Error(e.code(), config.where("map", e.key()) + ": " + e.reason());
  }
}

std::unique_ptr<Model> map_of(const Config& config, const std::optional<ChaosOptions>& chaos) {
  const bool formulas = is_formula_map(config);
  const auto definition = formulas ? definition_of(config) : nullptr;
  const std::string name = config.string("map", "name");
  const ParamValues params = map_params(config);
  try {
    if (formulas) return chaos ? make_model(definition, params, *chaos) : make_model(definition, params);
    return chaos ? make_model(name, params, *chaos) : make_model(name, params);
  } catch (const formula::DefinitionError& e) {
    throw Error(e.code(), config.where("map", e.key()) + ": " + e.reason());
  } catch (const Error& e) {
    throw Error(e.code(), config.where("map") + ": " + e.what());
  }
}

ParamValues map_params(const Config& config) {
  const bool formulas = is_formula_map(config);
  ParamValues params;
  for (const auto& key : config.keys("map"))
    if (std::find(formula::map_keys.begin(), formula::map_keys.end(), key) ==
            formula::map_keys.end() ||
        (!formulas && key != "name"))
      params[key] = config.number("map", key);
  return params;
}

bool names_file(const std::string& map) {
  return map.size() >= 5 && map.compare(map.size() - 5, 5, ".toml") == 0;
}

Config formula_map_file(const std::string& map, const ParamValues& params) {
  Config config = Config::load(map);
  if (!is_formula_map(config))
    throw usage_error(config.where("map") + ": --map " + map +
                      ": the file's [map] is not written as formulas (it has no form); name a "
                      "built-in map by its name");
  for (const auto& [name, value] : params) config.set("map." + name + "=" + number_text(value));
  return config;
}

std::unique_ptr<Model> map_named(const std::string& map, const ParamValues& params,
                                 const std::optional<ChaosOptions>& chaos) {
  if (!names_file(map)) return chaos ? make_model(map, params, *chaos) : make_model(map, params);
  return map_of(formula_map_file(map, params), chaos);
}

}  // namespace qmaps
