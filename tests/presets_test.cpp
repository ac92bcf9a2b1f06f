// Every preset in ensembles/presets runs, shrunk by overrides to a few orbits and steps, and
// writes each observer it configures: its histograms, sections and invariant image, holding
// samples, with little outside their ranges.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "ensembles/config/config.hpp"
#include "core/io/h5.hpp"
#include "kernels/catalogue.hpp"
#include "run_process.hpp"
#include "h5_read.hpp"

namespace qmaps::testing {
namespace {

std::vector<std::string> preset_paths() {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(QMAPS_SOURCE_DIR "/ensembles/presets"))
    if (e.path().extension() == ".toml") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

// Samples outside a histogram's ranges are at most 1% of them.
void expect_mostly_inside(const h5::Group& g, const std::string& what) {
  const auto samples = g.attr_int64("samples");
  EXPECT_GT(samples, 0) << what;
  EXPECT_LE(100 * (g.attr_int64("underflow") + g.attr_int64("overflow")), samples) << what;
}

TEST(Presets, EveryMapOfTheListHasOneAndEachPresetRunsAMapOfTheList) {
  std::set<std::string> names, maps;
  for (const auto& p : preset_paths()) {
    names.insert(fs::path(p).stem().string());
    maps.insert(Config::load(p).string("map", "name"));
  }
  for (const MapEntry& m : catalogue()) {
    EXPECT_TRUE(names.count(std::string(m.facts->preset))) << m.name;
    maps.erase(std::string(m.name));
  }
  EXPECT_TRUE(maps.empty()) << "a preset runs a map that is not in kernels/maps.hpp";
}

TEST(Presets, EachRunsSmallAndWritesItsObservers) {
  for (const auto& path : preset_paths()) {
    SCOPED_TRACE(path);
    const Config preset = Config::load(path);
    const std::string kind = preset.string_or("ensemble", "kind", "box");
    const bool grid = kind == "grid" || preset.string_or("ensemble", "sampling", "") == "grid";
    TempDir dir;
    const Result r = run({"run", path, "--set", grid ? "ensemble.points=6" : "ensemble.orbits=300",
                          "--set", "run.steps=300", "--out", "small.h5", "--quiet"},
                         dir);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(Contains(r.err, "0 escaped")) << "bounded orbits";
    const auto file = h5::File::open_read(dir / "small.h5");
    const auto root = file.root();
    EXPECT_EQ(root.attr_string("map"), preset.string("map", "name"));
    EXPECT_EQ(root.attr_string("ensemble"), kind);
    ASSERT_GT(preset.entries("histogram") + preset.entries("section"), 0u);
    for (std::size_t i = 0; i < preset.entries("histogram"); ++i) {
      const std::string name = preset.string("histogram[" + std::to_string(i) + "]", "name");
      expect_mostly_inside(root.open_group("histograms").open_group(name), name);
    }
    for (std::size_t i = 0; i < preset.entries("section"); ++i) {
      const std::string name = preset.string("section[" + std::to_string(i) + "]", "name");
      const auto section = root.open_group("sections").open_group(name);
      expect_mostly_inside(section, name);
      EXPECT_GT(testing::all_int64(section, "orbit").size(), 0u) << name;
    }
    ASSERT_TRUE(preset.has("invariant_image", "x"));
    expect_mostly_inside(root.open_group("invariants").open_group("image"), "invariant image");
  }
}

}  // namespace
}  // namespace qmaps::testing
