#include "core/params.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "core/error.hpp"

namespace qmaps {

std::vector<double> resolve_params(std::string_view map, std::span<const ParamSpec> specs,
                                   const ParamValues& given) {
  const auto known = [&](std::string_view name) {
    for (const auto& s : specs)
      if (s.name == name) return true;
    return false;
  };
  for (const auto& [name, value] : given) {
    if (known(name)) continue;
    std::ostringstream msg;
    msg << "map '" << map << "' has no parameter '" << name << "' (its parameters:";
    for (const auto& s : specs) msg << ' ' << s.name;
    msg << ')';
    throw usage_error(msg.str());
  }
  std::vector<double> values;
  for (const auto& s : specs) {
    const auto it = given.find(s.name);
    if (it == given.end() && s.required())
      throw usage_error("map '" + std::string(map) + "': parameter '" + std::string(s.name) +
                        "' is missing (" + std::string(s.meaning) + ")");
    const double v = it == given.end() ? s.default_value : it->second;
    if (it == given.end() && s.optional && std::isnan(v)) {
      values.push_back(v);
      continue;
    }
    if (!std::isfinite(v))
      throw usage_error("map '" + std::string(map) + "': parameter '" + std::string(s.name) +
                        "' must be finite");
    values.push_back(v);
  }
  return values;
}

void check_step(std::string_view map, std::string_view name, double step) {
  const std::string who = std::string(map) + ": " + std::string(name);
  if (!(step > 0)) throw usage_error(who + " must be > 0 (got " + number_text(step) + ")");
  const double smallest = std::sqrt(std::numeric_limits<double>::min());
  const double largest = std::sqrt(std::numeric_limits<double>::max());
  if (!(step * step >= std::numeric_limits<double>::min()))
    throw usage_error(who + " = " + number_text(step) + " is too small: " + std::string(name) +
                      "^2 must be a normal number (" + std::string(name) +
                      " >= " + number_text(smallest) + ")");
  if (!(step < largest))
    throw usage_error(who + " = " + number_text(step) + " is too large: " + std::string(name) +
                      "^2 must be finite (" + std::string(name) + " < " + number_text(largest) +
                      ")");
}

}  // namespace qmaps
