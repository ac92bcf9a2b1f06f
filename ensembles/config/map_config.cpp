#include "ensembles/config/map_config.hpp"

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
