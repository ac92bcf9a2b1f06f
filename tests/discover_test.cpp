// Invariant discovery (core/invariant_discovery.hpp, docs/discover.md): from the orbits alone, the
// null space of the step differences of the monomials holds
// - suris' H, I1, I2 (two independent) and case2's H1, H2, I1, I2 (two independent), at degree 4;
// - at degree 8 also their products (five in all for suris);
// - the flow's H and its case's second integral in an integrable case, to the integrator's
//   accuracy;
// - only H (and nothing else) for the chaotic flow β = α, δ = 12α, A = B = 0;
// - from maps written as formulas (ensembles/presets): Suris' H, I1, I2 again, the McMillan map's
//   invariant among the two variables it moves, and nothing for Suris kicked by ε q1² q2, whose
//   kick breaks I1 and I2 and leaves no energy-like polynomial either (its map is variational,
//   with no discrete energy conserved exactly);
// and `qmaps discover` prints them, and refuses bad input with exit 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/invariant_data.hpp"
#include "core/invariant_discovery.hpp"
#include "ensembles/kinds/box.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "kernels/catalogue.hpp"
#include "run_process.hpp"

namespace qmaps {
namespace {

// A known invariant (the map's own formula) is written over the monomials by a least-squares fit
// of its values on sample states; a polynomial of the degree fits to round-off.
constexpr double fit_tolerance = 1e-9;
// The part of a known invariant's (scaled) coefficient vector outside the discovered null space:
// round-off for the maps, the integrator's error for the flow.
constexpr double map_span_tolerance = 1e-7;
constexpr double flow_span_tolerance = 1e-4;
// The null space's separation from the rest of the spectrum, σ_k/σ_{k+1}: at least this.
constexpr double map_gap_minimum = 1e6;
constexpr double flow_gap_minimum = 1e3;
// At degree 8 (suris) the gap is smaller, and the discovered span is as accurate as 1/gap.
constexpr double degree_eight_gap_minimum = 1e3;
constexpr double degree_eight_span_tolerance = 1e-3;

struct Found {
  std::unique_ptr<Model> model;
  Monomials monomials;
  Discovery discovery;
  std::vector<std::vector<double>> states;   // sample states to evaluate known invariants at
  std::vector<std::vector<double>> samples;  // and their discovery variables, to fit them on
};

// Discovery on `orbits` orbits of the model from the box [−q, q]⁴ (seed 7), `steps` steps each.
Found find(std::unique_ptr<Model> model, int degree, std::size_t orbits, long long steps,
           double threshold, double q = 0.5) {  // threshold 0: at the largest gap
  const std::string map(model->name());
  Found f{std::move(model), Monomials(1, 1), {}, {}, {}};
  const auto variables = discovery_variables(*f.model);
  f.monomials = Monomials(variables.size(), degree);
  const Box box({{{-q, q}, {-q, q}, {-q, q}, {-q, q}}}, 7, orbits);
  Ensemble e = f.model->start(generate(box).points, Start::taylor, 1e8);
  // Samples for fitting known invariants: three per monomial, from another draw of the box.
  const Box more({{{-q, q}, {-q, q}, {-q, q}, {-q, q}}}, 8, 3 * f.monomials.size());
  const Ensemble s = f.model->start(generate(more).points, Start::taylor, 1e8);
  for (std::size_t i = 0; i < s.orbits; ++i) {
    std::vector<double> state, x;
    for (std::size_t k = 0; k < s.state.size(); ++k) state.push_back(s.state[k][i]);
    for (std::size_t k : variables) x.push_back(s.state[k][i]);
    f.states.push_back(state);
    f.samples.push_back(x);
  }
  DifferenceRows rows(f.monomials);
  const StepsAdded added = add_steps(*f.model, e, steps, 1e8, rows);
  EXPECT_EQ(added.escaped, 0u) << map;
  DiscoveryOptions options;
  options.threshold = threshold;
  f.discovery = discover(rows, options);
  const Discovery& d = f.discovery;
  std::printf("[ discover ] %s, degree %d: %zu rows, %zu monomials, null space %zu, gap %.3g, "
              "smallest sigma %.3g, largest non-null %.3g\n",
              map.c_str(), degree, d.rows, d.monomials, d.dimension, d.gap,
              d.relative.back(), d.relative[d.monomials - d.dimension - 1]);
  return f;
}
Found find(std::string_view map, const ParamValues& params, int degree, std::size_t orbits,
           long long steps, double threshold, double q = 0.5) {
  return find(make_model(map, params), degree, orbits, steps, threshold, q);
}
// A map written as formulas, from its preset.
std::unique_ptr<Model> preset_map(const std::string& name) {
  return map_of(Config::load(QMAPS_SOURCE_DIR "/ensembles/presets/" + name + ".toml"));
}

// Whether the map's invariant `name` (its own formula, Model::invariants_of) is a polynomial of
// the degree and lies in the discovered span.
void expect_in_span(const Found& f, const std::string& name, double span_tolerance) {
  const auto& names = f.model->invariant_names();
  const auto at = std::find(names.begin(), names.end(), name) - names.begin();
  ASSERT_LT(static_cast<std::size_t>(at), names.size()) << name;
  std::vector<double> values;
  for (const auto& x : f.states) values.push_back(f.model->invariants_of(x)[static_cast<std::size_t>(at)]);
  const PolynomialFit fit = fit_polynomial(f.monomials, f.samples, values);
  EXPECT_LT(fit.residual, fit_tolerance) << name << " is not a polynomial of this degree";
  const double outside = outside_null_space(f.discovery, fit.coefficients);
  std::printf("[ discover ] %s: fit residual %.3g, outside the null space %.3g\n", name.c_str(),
              fit.residual, outside);
  EXPECT_LT(outside, span_tolerance) << name;
}

const ParamValues suris = {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}};
const ParamValues case2 = {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}};
// Case I of the continuous system, and the chaotic homogeneous quartic of tests/chaos_test.cpp.
const ParamValues flow_case1 = {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"beta", 0.9},
                                {"delta", 1.8}, {"h", 0.02}};
const ParamValues flow_chaotic = {{"A", 0.0}, {"B", 0.0}, {"alpha", 0.25}, {"beta", 0.25},
                                  {"delta", 3.0}, {"h", 0.02}};

TEST(Discover, SurisInvariantsAtDegreeFour) {
  const Found f = find("suris", suris, 4, 100, 100, 0);
  EXPECT_EQ(f.discovery.dimension, 2u);
  EXPECT_GT(f.discovery.gap, map_gap_minimum);
  for (const char* name : {"H", "I1", "I2"}) expect_in_span(f, name, map_span_tolerance);
}

TEST(Discover, SurisProductsOfInvariantsAtDegreeEight) {
  // At degree 8 the monomials of (q_n, q_{n+1}), nearly equal, are ill-conditioned: the rest of
  // the spectrum reaches down to 3e-13 (docs/discover.md), so the gap is smaller.
  const Found f = find("suris", suris, 8, 100, 100, 0);
  EXPECT_EQ(f.discovery.dimension, 5u);  // H, I1, H², H I1, I1²
  EXPECT_GT(f.discovery.gap, degree_eight_gap_minimum);
  for (const char* name : {"H", "I1", "I2"}) expect_in_span(f, name, degree_eight_span_tolerance);
}

TEST(Discover, Case2InvariantsAtDegreeFour) {
  const Found f = find("case2", case2, 4, 100, 100, 0);
  EXPECT_EQ(f.discovery.dimension, 2u);
  EXPECT_GT(f.discovery.gap, map_gap_minimum);
  for (const char* name : {"H1", "H2", "I1", "I2"}) expect_in_span(f, name, map_span_tolerance);
}

TEST(Discover, FlowEnergyAndSecondIntegralInCaseOne) {
  const Found f = find("flow", flow_case1, 4, 100, 200, 0);
  EXPECT_EQ(f.discovery.dimension, 2u);
  EXPECT_GT(f.discovery.gap, flow_gap_minimum);
  for (const char* name : {"H", "I_case1"}) expect_in_span(f, name, flow_span_tolerance);
}

TEST(Discover, ChaoticFlowHasOnlyItsEnergy) {
  for (int degree : {4, 6}) {
    const Found f = find("flow", flow_chaotic, degree, 100, 500, 0);
    EXPECT_EQ(f.discovery.dimension, 1u) << "degree " << degree;
    expect_in_span(f, "H", flow_span_tolerance);
  }
}

TEST(Discover, SurisWrittenAsFormulasHasTheBuiltInMapsInvariants) {
  const Found f = find(preset_map("suris-formulas"), 4, 100, 100, 0);
  EXPECT_EQ(f.discovery.dimension, 2u);
  EXPECT_GT(f.discovery.gap, map_gap_minimum);
  for (const char* name : {"H", "I1", "I2"}) expect_in_span(f, name, map_span_tolerance);
}

TEST(Discover, McMillanInvariantAmongTheVariablesItsMapMoves) {
  // one degree of freedom: q2 and p2 stay as they are, no variables of discovery
  const Found f = find(preset_map("mcmillan"), 4, 100, 200, 0);
  EXPECT_EQ(discovery_variable_names(*f.model), (std::vector<std::string>{"p1", "q1"}));
  EXPECT_EQ(f.discovery.dimension, 1u);
  EXPECT_GT(f.discovery.gap, map_gap_minimum);
  expect_in_span(f, "I", map_span_tolerance);
}

TEST(Discover, SurisKickedHasNoPolynomialInvariant) {
  // The kick −h² ∇(ε q1² q2) breaks I1 and I2, and the discrete energy H0 drifts: nothing is left.
  for (int degree : {4, 6}) {
    const Found f = find(preset_map("suris-kicked"), degree, 100, 200, 0);
    EXPECT_EQ(f.discovery.dimension, 0u) << "degree " << degree;
  }
}

TEST(Discover, ReducedFormIsCanonical) {
  // Two runs on different orbits give the same reduced basis, whatever rotation the SVD returns.
  const Found a = find("suris", suris, 4, 60, 100, 1e-9, 0.5);
  const Found b = find("suris", suris, 4, 80, 100, 0, 0.4);
  ASSERT_EQ(a.discovery.invariants.size(), 2u);
  ASSERT_EQ(b.discovery.invariants.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t j = 0; j < a.monomials.size(); ++j)
      EXPECT_NEAR(a.discovery.invariants[k][j], b.discovery.invariants[k][j], 1e-8)
          << "invariant " << k + 1 << ", " << a.monomials.text(j, std::vector<std::string>(4, "x"));
}

TEST(Discover, MonomialsCountAndOrder) {
  const Monomials m(4, 4);
  EXPECT_EQ(m.size(), 69u);
  EXPECT_EQ(Monomials::count(4, 4), 69.0);
  EXPECT_EQ(Monomials::count(4, 8), 494.0);
  // Beyond degree 1000 the count is a product of n factors: huge for any degree up to 2^63 − 1
  // (a difference of lgammas cancelled to 0 there, and the count came out negative).
  EXPECT_EQ(Monomials::count(4, 2000), 2004.0 * 2003 * 2002 * 2001 / 24 - 1);
  EXPECT_GT(Monomials::count(4, std::numeric_limits<long long>::max()), 1e70);
  const std::vector<std::string> names = {"q1", "q2", "p1", "p2"};
  EXPECT_EQ(m.text(0, names), "q1");
  EXPECT_EQ(m.text(4, names), "q1^2");
  EXPECT_EQ(m.text(5, names), "q1 q2");
  EXPECT_EQ(m.text(68, names), "p2^4");
  std::vector<double> c(m.size(), 0.0);
  c[4] = 1;
  c[13] = 0.5;   // p2^2: 4 + 10 − 1
  c[68] = -0.25;
  EXPECT_EQ(m.polynomial(c, names, 1e-6), "1 q1^2 + 0.5 p2^2 - 0.25 p2^4");
}

}  // namespace

namespace testing {
namespace {

const std::string preset = QMAPS_SOURCE_DIR "/ensembles/presets/suris.toml";

TEST(DiscoverCli, PrintsSurisInvariants) {
  TempDir dir;
  const Result r = run({"discover", preset, "--degree", "4", "--steps", "100", "--orbits", "50"}, dir);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "rows:       5000 steps, 69 monomials of degree 1 to 4\n"));
  EXPECT_TRUE(Contains(r.out, "null space: dimension 2 "));
  EXPECT_TRUE(Contains(r.out, "invariant 1: "));
  EXPECT_TRUE(Contains(r.out, "invariant 2: "));
  EXPECT_TRUE(Contains(r.out, "q1[n]^2"));
  std::printf("%s", r.out.c_str());
}

TEST(DiscoverCli, BadInputIsAUsageError) {
  TempDir dir;
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--degree", "0", "--steps", "10"}, "--degree must be >= 1"},
      {{"--degree", "40", "--steps", "10"}, "monomials of the 4 variables; at most"},
      {{"--degree", "9223372036854775807", "--steps", "10"}, "monomials of the 4 variables"},
      // Orbits below the escape bound whose monomials overflow give no rows: said as such.
      {{"--degree", "4", "--steps", "10", "--set", "ensemble.q1=[1e100, 1e101]", "--set",
        "run.escape_bound=1e300"},
       "(0 of 100 escaped; 1000 steps left out, their monomials beyond the largest double)"},
      {{"--degree", "4", "--steps", "10", "--orbits", "2"}, "too few rows: 2 orbits x 10 steps"},
      {{"--degree", "4", "--steps", "10", "--set", "map.name=nomap"}, "nomap"},
  };
  for (const auto& [args, message] : cases) {
    std::vector<std::string> all = {"discover", preset};
    all.insert(all.end(), args.begin(), args.end());
    const Result r = run(all, dir);
    EXPECT_EQ(r.status, 2) << message << ": " << r.err;
    EXPECT_TRUE(Contains(r.err, "qmaps: error: "));
    EXPECT_TRUE(Contains(r.err, message));
    EXPECT_EQ(r.out, "");
  }
}

// A flow's shell of one energy lies on the level set H = E: every (H − E)·g vanishes on the data
// and would be printed as an invariant (71 of them at degree 8); discover refuses, naming H.
TEST(DiscoverCli, RefusesOrbitsOnOneLevelSetOfAnInvariant) {
  TempDir dir;
  std::ofstream(dir / "shell.toml") << R"([map]
name = "flow"
A = 0.7
B = 0.3
alpha = 0.9
beta = 0.9
delta = 1.8
h = 0.02

[ensemble]
kind = "shell"
energy = 0.1
orbits = 100
q1 = [-0.3, 0.3]
q2 = [-0.3, 0.3]
p1 = [-0.3, 0.3]
)";
  const Result r = run({"discover", dir / "shell.toml", "--degree", "6", "--steps", "50"}, dir);
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_TRUE(Contains(r.err, "the 100 orbits lie on one level set of the map's invariant H "
                              "(H = 0.1 on every orbit, to "));
  EXPECT_TRUE(Contains(r.err, "give orbits spread over H's values"));
  EXPECT_EQ(r.out, "");
}

}  // namespace
}  // namespace testing
}  // namespace qmaps
