// libFuzzer target: the configuration as `qmaps run` reads it. The input is a TOML text, then
// after a NUL byte any number of `--set` assignments, one per line. Parsing, the overrides, the map
// with its parameters, a sweep's points, the observers and the initial-condition kind must either succeed or throw
// qmaps::Error (exit 2 or 3): any other exception, a crash or a sanitizer report is a finding.
#include <cstdint>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/config/observer_config.hpp"
#include "ensembles/config/sweep_config.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "kernels/catalogue.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace qmaps;
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  const auto nul = all.find('\0');
  try {
    Config config = Config::parse(all.substr(0, nul), "fuzz.toml");
    if (nul != std::string_view::npos) {
      std::string_view sets = all.substr(nul + 1);
      while (!sets.empty()) {
        const auto end = sets.find('\n');
        config.set(sets.substr(0, end));
        sets = end == std::string_view::npos ? std::string_view() : sets.substr(end + 1);
      }
    }
    ParamValues params;
    for (const auto& key : config.keys("map"))
      if (key != "name") params[key] = config.number("map", key);
    const auto model = make_model(config.string("map", "name"), params);
    if (const auto sweep = Sweep::from_config(config, *model))  // each point's map, at most 64
      for (std::size_t k = 0; k < sweep->points() && k < 64; ++k) map_of(sweep->config_of(config, k));
    const auto initial = InitialConditions::from_config(config, *model);
    // At most 4096 orbits and steps: the sections' slots stay small whatever the caps say.
    const long long steps = config.integer_or("run", "steps", 0);
    observers_from_config(config, *model, initial.orbits() < 4096 ? initial.orbits() : 4096,
                          steps < 4096 ? steps : 4096);
    config.reject_unknown();
  } catch (const Error&) {
  }
  return 0;
}
