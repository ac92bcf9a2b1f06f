// The integrability tests (integrability/, docs/integrability.md) on maps with known answers: the
// paper's rational maps and a McMillan map are integrable, with degrees growing as n²; the leapfrog,
// the flow's composition and the Hénon maps are not, with the entropies log 3, log 27, log 2 and
// log 3; over F_p the integrable maps' orbits keep their invariants, the quadratic Hénon map's
// periods follow R(x), and the three tests agree on every one of them. Bad options are exit 2,
// naming the option.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <iostream>

#include <flint/ulong_extras.h>

#include "core/map_concept.hpp"
#include "ensembles/program/commands.hpp"
#include "integrability/verdict.hpp"
#include "kernels/catalogue.hpp"
#include "run_process.hpp"

namespace qmaps {
namespace {

using namespace exact;
using testing::Contains;

// A built-in map at its example parameters, or a preset or fixture file.
ExactMap map_named(const std::string& name, ParamValues extra = {}) {
  for (const auto& e : catalogue())
    if (e.name == name) {
      ParamValues p = param_values(e.facts->example);
      for (const auto& [k, v] : extra) p[k] = v;
      return exact_map_named(name, p);
    }
  const std::string preset = QMAPS_SOURCE_DIR "/ensembles/presets/" + name + ".toml";
  const std::string fixture = QMAPS_FIXTURES_DIR "/maps/" + name + ".toml";
  return exact_map_named(std::filesystem::exists(preset) ? preset : fixture, extra);
}

std::string text(const std::vector<double>& d) {
  std::string s;
  for (const double v : d) s += (s.empty() ? "" : " ") + std::to_string(static_cast<long>(v));
  return s;
}

DegreeTest degrees(const ExactMap& m, long cap = 100000) {
  IntegrabilityOptions o;
  o = resolved(o, m);
  const DegreeTest t = degree_test(m, o.degree_primes, 2, 30, cap, 1);
  std::cout << m.name << ": d_n = " << text(t.runs.front().degrees) << "; "
            << to_string(t.growth.kind) << " " << t.growth.characteristic << "\n";
  return t;
}

TEST(Integrability, LeapfrogAndFlowGrowExponentially) {
  const DegreeTest leapfrog = degrees(map_named("leapfrog"));
  EXPECT_EQ(leapfrog.growth.kind, Growth::Kind::exponential);
  EXPECT_NEAR(leapfrog.growth.entropy, std::log(3.0), 1e-9);  // exact fit: d_n = 3^n
  // The flow of order 4 composes 3 cubic kicks: 27^n, to the cap of 10^6 (5 terms: the tail's
  // ratios, exact).
  const DegreeTest flow = degrees(map_named("flow", {{"order", 4}}), 1000000);
  EXPECT_EQ(flow.growth.kind, Growth::Kind::exponential);
  EXPECT_NEAR(flow.growth.entropy, std::log(27.0), 1e-9);
}

TEST(Integrability, TwoDimensionalMapsWithKnownAnswers) {
  const DegreeTest mcmillan = degrees(map_named("mcmillan"));
  EXPECT_EQ(mcmillan.growth.kind, Growth::Kind::polynomial);
  EXPECT_EQ(mcmillan.growth.degree, 2);
  const DegreeTest quadratic = degrees(map_named("henon-quadratic"));
  EXPECT_EQ(quadratic.growth.kind, Growth::Kind::exponential);
  EXPECT_NEAR(quadratic.growth.entropy, std::log(2.0), 1e-9);
  EXPECT_EQ(quadratic.runs.front().degrees[10], 1024);
  const DegreeTest cubic = degrees(map_named("henon-cubic"));
  EXPECT_EQ(cubic.growth.kind, Growth::Kind::exponential);
  EXPECT_NEAR(cubic.growth.entropy, std::log(3.0), 1e-9);
  EXPECT_EQ(cubic.runs.front().degrees[6], 729);
}

TEST(Integrability, IntegrableOrbitsModPKeepTheirInvariants) {
  for (const auto& [name, p] : {std::pair{"mcmillan", 1009}, std::pair{"mcmillan", 4001},
                                std::pair{"suris-formulas", 31}, std::pair{"suris-formulas", 61}}) {
    SCOPED_TRACE(std::string(name) + " mod " + std::to_string(p));
    const ExactMap m = map_named(name);
    ASSERT_TRUE(m.invariants_exact);
    const FieldOrbits f = finite_field_orbits(m, static_cast<std::uint64_t>(p), 200, 1 << 20, 1);
    EXPECT_EQ(f.level_checked, 64u);
    EXPECT_EQ(f.level_kept, 64u);
  }
  // The check can fail: Suris' energy is no invariant of the kicked map (at eps = 0 it is).
  EXPECT_FALSE(map_named("suris-kicked").invariants_exact);
  EXPECT_TRUE(map_named("suris-kicked", {{"eps", 0}}).invariants_exact);
}

TEST(Integrability, QuadraticHenonPeriodsFollowTheUniversalLawAtOnePercent) {
  const FieldOrbits henon = finite_field_orbits(map_named("henon-quadratic"), 10007, 1000, 1 << 22, 1);
  std::cout << "henon-quadratic mod 10007: D = " << henon.ks_distance << ", p-value "
            << henon.p_value << "\n";
  EXPECT_EQ(henon.periods.size(), 1000u);
  EXPECT_GE(henon.p_value, 0.01);
  EXPECT_LE(henon.ks_distance, near_R);
  const FieldOrbits mcmillan = finite_field_orbits(map_named("mcmillan"), 10007, 1000, 1 << 22, 1);
  std::cout << "mcmillan mod 10007: D = " << mcmillan.ks_distance << "\n";
  EXPECT_GE(mcmillan.ks_distance, far_from_R);
  EXPECT_LT(mcmillan.p_value, 0.01);
}

TEST(Integrability, FourDimensionalMapsFallApartInTheirDistanceFromR) {
  for (const std::uint64_t p : {61, 101}) {
    const FieldOrbits leapfrog = finite_field_orbits(map_named("leapfrog"), p, 1000, 1 << 24, 1);
    const FieldOrbits suris = finite_field_orbits(map_named("suris-formulas"), p, 1000, 1 << 24, 1);
    std::cout << "mod " << p << ": D(leapfrog) = " << leapfrog.ks_distance << " of "
              << leapfrog.periods.size() << " periods, D(suris) = " << suris.ks_distance << " of "
              << suris.periods.size() << " (" << suris.singular << " singular)\n";
    EXPECT_LE(leapfrog.ks_distance, near_R);
    EXPECT_GE(suris.ks_distance, far_from_R);
    EXPECT_GT(suris.singular, 0u);  // 1 + 2 alpha h^2 |q|^2 vanishes mod p: counted, no crash
  }
}

TEST(Integrability, PeriodsAreTheScalarResiduesAndDoNotDependOnTheThreads) {
  const ExactMap m = map_named("henon-quadratic");
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const FieldOrbits one = finite_field_orbits(m, 1009, 300, 1 << 20, 7);
  omp_set_num_threads(2);
  const FieldOrbits two = finite_field_orbits(m, 1009, 300, 1 << 20, 7);
  omp_set_num_threads(threads);
  EXPECT_EQ(one.periods, two.periods);
  // The first orbits again, one residue at a time (FLINT's nmod arithmetic).
  PrimeField field(1009);
  for (std::size_t i = 0; i < 8; ++i) {
    const auto start = orbit_start(m, 7, i, 1009);
    State<Residue> x;
    for (std::size_t k = 0; k < 4; ++k) x[k] = Residue::of(start[k]);
    const State<Residue> first = x;
    std::uint64_t period = 0;
    do {
      m.step(x);
      ++period;
    } while (!(x == first) && period < (1 << 20));
    EXPECT_EQ(period, one.periods[i]);
  }
}

TEST(Integrability, TheThreeTestsAgreeOnEveryMapWithAKnownAnswer) {
  IntegrabilityOptions o;
  o.orbits = 400;
  const auto check = [&](const ExactMap& m, Says expected, bool all_three) {
    SCOPED_TRACE(m.name);
    const Report r = integrability_report(m, resolved(o, m));
    std::cout << m.name << ": " << to_string(r.verdict) << " (" << r.reason << "); D = "
              << r.fields.back().ks_distance << " of " << r.fields.back().periods.size()
              << " periods\n";
    EXPECT_EQ(r.verdict, expected);
    EXPECT_EQ(r.tests_agree, all_three);
    return r;
  };
  // The paper's rational maps: their degrees (the report's own degree test) grow as n², the
  // characteristic polynomial of their recurrence having (x - 1)^3.
  for (const char* name : {"suris", "case2", "case2-staggered", "case2-hky"}) {
    const Report r = check(map_named(name), Says::integrable, true);
    SCOPED_TRACE(name);
    const DegreeTest& t = r.degrees;
    EXPECT_TRUE(t.agree);
    EXPECT_EQ(t.runs.front().degrees.size(), 31u);
    ASSERT_TRUE(t.growth.recurrence);
    EXPECT_EQ(t.growth.kind, Growth::Kind::polynomial);
    EXPECT_EQ(t.growth.degree, 2);
    EXPECT_TRUE(Contains(t.growth.characteristic, "(x-1)^3"));
  }
  for (const char* name : {"mcmillan", "suris-formulas"})
    check(map_named(name), Says::integrable, true);
  for (const char* name : {"leapfrog", "henon-quadratic", "henon-cubic"})
    check(map_named(name), Says::not_integrable, true);
  check(map_named("flow", {{"order", 4}}), Says::not_integrable, true);
  // Kicked, Suris' map is not integrable by its degrees and heights; mod p its long orbits nearly
  // all meet a point where 1 + 2 alpha h^2 |q|^2 vanishes, so too few come back to judge them.
  check(map_named("suris-kicked"), Says::not_integrable, false);
}

TEST(Integrability, BadOptionsAreExitTwoNamingTheOption) {
  const testing::TempDir dir;
  const auto run = [&](std::vector<std::string> args) {
    args.insert(args.begin(), "integrability");
    return testing::run(args, dir);
  };
  const std::string too_large = std::to_string(n_nextprime(1ULL << 26, 1));
  const std::string presets = QMAPS_SOURCE_DIR "/ensembles/presets/";
  for (const auto& [args, says] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"--map", presets + "mcmillan.toml", "--field-primes", "1009,100"}, "--field-primes: 100 is not prime"},
           {{"--map", presets + "mcmillan.toml", "--field-primes", too_large}, "--field-primes: " + too_large + " is outside"},
           {{"--map", presets + "mcmillan.toml", "--degree-primes", std::to_string(n_nextprime(1ULL << 62, 1))}, "--degree-primes"},
           {{"--map", presets + "mcmillan.toml", "--degree-cap", "1000000000000000"}, "--degree-cap"},
           {{"--map", "case3"}, "case3: its step solves a quartic"},
           {{"--map", presets + "froeschle.toml"}, "[map] step: line 1, column"},
           {{"--map", "suris", "--set", "A=0.7"}, "parameter 'B' is missing"}}) {
    SCOPED_TRACE(says);
    const auto r = run(args);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(Contains(r.err, says));
  }
}

TEST(Integrability, AMapWhoseHeightsExplodeStopsAtTheCaps) {
  // x^(64^5) in one step: degrees past any cap, heights of 10^9 bits and more; stopped, not a crash.
  const testing::TempDir dir;
  testing::write_text(dir / "tower.toml", "[map]\nname = \"tower\"\nform = \"phase\"\n"
                      "step = \"q1 = ((((p1^64)^64)^64)^64)^64 + q1; p1 = p1 + q1\"\n");
  const auto r = testing::run({"integrability", "--map", dir / "tower.toml", "--field-primes", "101",
                               "--orbits", "20", "--steps", "3", "--height-steps", "3"}, dir);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "stopped by the degree cap (20000) at step 1"));
  EXPECT_TRUE(Contains(r.out, "stopped by the height cap"));
}

}  // namespace
}  // namespace qmaps
