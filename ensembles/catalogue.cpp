#include "ensembles/catalogue.hpp"

#include <array>
#include <optional>
#include <string>

#include "core/error.hpp"
#include "core/model_of.hpp"
#include "kernels/case2.hpp"
#include "kernels/case2_hky.hpp"
#include "kernels/case3.hpp"
#include "kernels/flow.hpp"
#include "kernels/suris.hpp"

namespace qmaps {
namespace {

template <class Map>
MapEntry entry() {
  return {Map::name, Map::summary, Map::equations, Map::invariant_summary, Map::params,
          [](const ParamValues& p) -> std::unique_ptr<Model> {
            return std::make_unique<ModelOf<Map>>(p);
          }};
}

const std::array maps = {entry<kernels::Suris>(),  entry<kernels::Case2>(),
                         entry<kernels::Case2Staggered>(), entry<kernels::Case2Hky>(),
                         entry<kernels::Case3>(),  entry<kernels::Flow>(),
                         entry<kernels::Leapfrog>()};

}  // namespace

std::optional<double> number_in(const std::string& text) {
  std::size_t used = 0;
  try {
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  return std::nullopt;
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

std::span<const MapEntry> catalogue() { return maps; }

std::unique_ptr<Model> make_model(std::string_view name, const ParamValues& params) {
  for (const auto& m : maps)
    if (m.name == name) return m.make(params);
  std::string known;
  for (const auto& m : maps) known += (known.empty() ? "" : ", ") + std::string(m.name);
  throw usage_error("unknown map '" + std::string(name) + "' (known maps: " + known + ")");
}

}  // namespace qmaps
