#pragma once
// A map's parameters: what each one is called and means, and the values a run resolves them to.
#include <cmath>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace qmaps {

struct ParamSpec {
  std::string_view name;
  std::string_view meaning;
  double default_value = std::numeric_limits<double>::quiet_NaN();  // NaN: no default
  bool optional = false;  // without a default: may be left out, and resolves to NaN then
  bool required() const { return std::isnan(default_value) && !optional; }
};

// Values given by the user, by name.
using ParamValues = std::map<std::string, double, std::less<>>;

// The values in the order of `specs`: defaults filled in, NaN for optional ones left out; an
// unknown, missing or non-finite value is a usage error naming the map and the parameter.
std::vector<double> resolve_params(std::string_view map, std::span<const ParamSpec> specs,
                                   const ParamValues& given);

// A map's step `name` (h, ds): > 0, and its square a normal, finite number, so that the
// coefficients built from it (1/h², 2αh², …) are finite and every invariant is a number; else a
// usage error naming the map, the parameter and the limit.
void check_step(std::string_view map, std::string_view name, double step);

}  // namespace qmaps
