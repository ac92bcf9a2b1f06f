#include "kernels/catalogue.hpp"

#include <array>
#include <optional>
#include <string>

#include "core/error.hpp"
#include "core/model_of.hpp"
#include "kernels/maps.hpp"

namespace qmaps {
namespace {

template <KernelMap Map>
MapEntry entry() {
  return {Map::name, Map::summary, Map::equations, Map::invariant_summary, Map::params,
          &Map::facts, [](const ParamValues& p) -> std::unique_ptr<Model> {
            return std::make_unique<ModelOf<Map>>(p);
          }};
}

// Built on first use (other translation units' static initializers may ask for it).
const auto& maps() {
  static const auto list = std::apply(
      [](auto... map) { return std::array{entry<decltype(map)>()...}; }, kernels::Maps{});
  return list;
}

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

std::span<const MapEntry> catalogue() { return maps(); }

std::unique_ptr<Model> make_model(std::string_view name, const ParamValues& params) {
  for (const auto& m : maps())
    if (m.name == name) return m.make(params);
  std::string known;
  for (const auto& m : maps()) known += (known.empty() ? "" : ", ") + std::string(m.name);
  throw usage_error("unknown map '" + std::string(name) + "' (known maps: " + known + ")");
}

}  // namespace qmaps
