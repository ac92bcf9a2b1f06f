// Every preset in ensembles/presets runs, shrunk by overrides to a few orbits and steps, and
// writes each observer it configures: its histograms, sections and invariant image, holding
// samples, with little outside their ranges.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "ensembles/config/config.hpp"
#include "ensembles/io/h5.hpp"
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

TEST(Presets, EveryMapOfTheListHasOneAndEachPresetRunsAMapOfTheListOrItsFormulas) {
  std::set<std::string> names, maps;
  for (const auto& p : preset_paths()) {
    names.insert(fs::path(p).stem().string());
    const Config preset = Config::load(p);
    if (!preset.has("map", "form")) maps.insert(preset.string("map", "name"));  // not formulas
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
    if (preset.entries("sweep") > 0) continue;  // the scans: below
    const std::string kind = preset.string_or("ensemble", "kind", "box");
    const bool grid = kind == "grid" || preset.string_or("ensemble", "sampling", "") == "grid";
    // A grid keeps its shape, each axis cut to at most 6 points.
    std::string points = "ensemble.points=[";
    if (grid)
      for (const auto n : preset.range_or_integer("ensemble", "points"))
        points += (points.back() == '[' ? "" : ", ") + std::to_string(std::min<std::int64_t>(n, 6));
    points += "]";
    TempDir dir;
    const bool tunes = preset.has_section("tunes");  // two windows of 128 steps in the 300
    std::vector<std::string> args{"run", path, "--set", grid ? points : "ensemble.orbits=300",
                                  "--set", "run.steps=300", "--out", "small.h5", "--quiet"};
    if (tunes) args.insert(args.end(), {"--set", "tunes.window=128"});
    const Result r = run(args, dir);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(Contains(r.err, "0 escaped")) << "bounded orbits";
    const auto file = h5::File::open_read(dir / "small.h5");
    const auto root = file.root();
    EXPECT_EQ(root.attr_string("map"), preset.string("map", "name"));
    EXPECT_EQ(root.attr_string("ensemble"), kind);
    ASSERT_GT(preset.entries("histogram") + preset.entries("section") + (tunes ? 1 : 0), 0u);
    if (tunes) {
      const auto map = root.open_group("tunes").open_group("frequency_map");
      expect_mostly_inside(map, "frequency map");
      EXPECT_EQ(map.attr_int64("samples"), root.open_group("tunes").attr_int64("regular") +
                                               root.open_group("tunes").attr_int64("chaotic"));
    }
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
    if (preset.has("invariant_image", "x"))
      expect_mostly_inside(root.open_group("invariants").open_group("image"), "invariant image");
  }
}

// A scan preset with its axes replaced by these lists of values, run at full size per point.
Result run_scan(const std::string& preset, const std::string& beta_over_alpha,
                const std::string& delta_over_alpha, const TempDir& dir) {
  std::string text = read_text(QMAPS_SOURCE_DIR "/ensembles/presets/" + preset + ".toml");
  text = text.substr(0, text.find("[[sweep]]")) + "[[sweep]]\nparameter = \"beta/alpha\"\nvalues = " +
         beta_over_alpha + "\n\n[[sweep]]\nparameter = \"delta/alpha\"\nvalues = " +
         delta_over_alpha + "\n";
  std::ofstream(dir / "scan.toml") << text;
  return run({"run", "scan.toml", "--out", "scan.h5", "--quiet"}, dir);
}

// The scans' known integrable points and the separable row delta = 0 come out regular (no orbit
// of 64 chaotic), against the strongly chaotic row delta/alpha = 40 (most orbits chaotic).
TEST(Presets, ScansFindTheKnownCasesRegularAndChaosAroundThem) {
  struct Scan {
    std::string preset, beta, delta;
    std::vector<std::string> cases;  // the second integral the map names at each point, or ""
  };
  const std::vector<Scan> scans = {
      {"scan-b4a", "[1, 8, 16]", "[0, 2, 6, 12, 40]",
       {"", "I_case1", "", "", "", "", "", "I_case4", "", "", "", "", "", "I_case3", ""}},
      {"scan-a-eq-b", "[1, 4]", "[0, 2, 6, 40]",
       {"", "I_case1", "I_case2", "", "", "", "", ""}}};
  for (const auto& scan : scans) {
    SCOPED_TRACE(scan.preset);
    TempDir dir;
    const Result r = run_scan(scan.preset, scan.beta, scan.delta, dir);
    ASSERT_EQ(r.status, 0) << r.err;
    const auto file = h5::File::open_read(dir / "scan.h5");
    const auto sweep = file.root().open_group("sweep");
    const auto delta = all_doubles(sweep.open_group("axes"), "delta_over_alpha");
    const auto fraction = all_doubles(sweep, "chaotic_fraction");
    const auto escaped = all_int64(sweep, "escaped");
    ASSERT_EQ(fraction.size(), scan.cases.size());
    for (std::size_t k = 0; k < fraction.size(); ++k) {
      const double d = delta[k % delta.size()];
      std::string name = std::to_string(k);  // zero-padded to the last point's digits
      if (fraction.size() > 10 && k < 10) name.insert(name.begin(), '0');
      const auto invariants =
          sweep.open_group("runs").open_group(name).open_group("invariants").members();
      SCOPED_TRACE("point " + std::to_string(k) + ", delta/alpha = " + std::to_string(d));
      EXPECT_EQ(escaped[k], 0);
      const std::string second = invariants.size() == 2 ? invariants[1] : "";
      EXPECT_EQ(second, scan.cases[k]);
      if (!scan.cases[k].empty() || d == 0) {
        EXPECT_EQ(fraction[k], 0.0);
      }
      if (d == 40) {
        EXPECT_GE(fraction[k], 0.5);
      }
    }
  }
}

}  // namespace
}  // namespace qmaps::testing
