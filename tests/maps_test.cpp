// The list of maps (kernels/maps.hpp) and what each map brings with it: every map satisfies the
// KernelMap concept, has a preset in ensembles/presets that runs it, and a section of docs/maps.md
// whose heading names it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "ensembles/config/config.hpp"
#include "kernels/catalogue.hpp"
#include "kernels/maps.hpp"

namespace qmaps {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(Maps, EveryMapOfTheListIsAKernelMapInTheCatalogue) {
  std::size_t count = 0;
  kernels::for_each_map([&](auto map) {
    using Map = decltype(map);
    static_assert(KernelMap<Map>);
    ASSERT_LT(count, catalogue().size());
    EXPECT_EQ(catalogue()[count].name, Map::name);
    EXPECT_EQ(catalogue()[count].facts, &Map::facts);
    ++count;
  });
  EXPECT_EQ(count, catalogue().size());
  EXPECT_EQ(count, kernels::built_in_maps);
}

TEST(Maps, EveryMapHasAPresetThatRunsIt) {
  for (const MapEntry& m : catalogue()) {
    const fs::path preset =
        fs::path(QMAPS_SOURCE_DIR) / "ensembles/presets" / (std::string(m.facts->preset) + ".toml");
    ASSERT_TRUE(fs::is_regular_file(preset)) << m.name << ": no preset " << preset;
    EXPECT_EQ(Config::load(preset).string("map", "name"), m.name) << preset;
  }
}

TEST(Maps, EveryMapHasASectionOfDocsMaps) {
  const std::string docs = read(fs::path(QMAPS_SOURCE_DIR) / "docs/maps.md");
  std::set<std::string> headings;
  std::istringstream lines(docs);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("## ", 0) == 0) headings.insert(line);
  for (const MapEntry& m : catalogue()) {
    std::string quoted = "`";
    quoted.append(m.name).append("`");
    bool found = false;
    for (const auto& h : headings) found |= h.find(quoted) != std::string::npos;
    EXPECT_TRUE(found) << m.name << ": no heading of docs/maps.md names `" << m.name << "`";
  }
}

TEST(Maps, EveryExampleResolvesAndItsEscapingSetHasANegativeQuartic) {
  for (const MapEntry& m : catalogue()) {
    EXPECT_NO_THROW(m.make(param_values(m.facts->example))) << m.name;
    const auto escaping = param_values(m.facts->escaping);
    EXPECT_NO_THROW(m.make(escaping)) << m.name;
    EXPECT_LT(escaping.at("alpha"), 0) << m.name;
    EXPECT_TRUE(param_values(m.facts->example).count(std::string(m.facts->step))) << m.name;
  }
}

// A step whose square is not a normal number would make the coefficients (1/h², …) infinite and
// the invariants NaN while no orbit escapes: every map rejects it, naming the limit.
TEST(Maps, EveryMapRejectsAStepWhoseSquareIsNotANormalNumber) {
  for (const MapEntry& m : catalogue()) {
    for (double step : {1e-300, 1e-320, 1e160}) {
      ParamValues p = param_values(m.facts->example);
      p[std::string(m.facts->step)] = step;
      try {
        m.make(p);
        ADD_FAILURE() << m.name << " accepted " << m.facts->step << " = " << step;
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::usage) << m.name;
        EXPECT_NE(std::string(e.what()).find(step < 1 ? "is too small" : "is too large"),
                  std::string::npos)
            << e.what();
      }
    }
  }
}

}  // namespace
}  // namespace qmaps
