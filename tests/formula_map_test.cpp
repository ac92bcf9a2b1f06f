// Maps written as formulas (kernels/formula_map.hpp, docs/formulas.md): a definition's errors at
// their key, line and column; Suris written as formulas (ensembles/presets/suris-formulas.toml)
// against the built-in map, byte for byte on every path, with its chaos record; written naturally
// (a·b + c) and as linear equations, within 1e-12 of it; a singular system as that orbit's fault;
// the tangent against long-double central differences, det J = 1 for the symplectic classics; K
// chains stepped together, the state resident in registers, as the single steps; the McMillan
// map's invariant to round-off.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "core/dual.hpp"
#include "core/escape.hpp"
#include "ensemble_fixtures.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "isas_run.hpp"
#include "kernels/formula_map.hpp"
#include "kernels/suris.hpp"

namespace qmaps {
namespace {

using kernels::Formula;

Config preset(const std::string& name) {
  return Config::load(QMAPS_SOURCE_DIR "/ensembles/presets/" + name + ".toml");
}

// The message of making the map of this [map] table, or "".
std::string error_of(const std::string& map_table) {
  try {
    const Config config = Config::parse("[map]\n" + map_table, "test.toml");
    map_of(config);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::usage);
    return e.what();
  }
  return "";
}

TEST(FormulaMap, ErrorsNameTheKeyLineAndColumn) {
  const std::string two_step =
      "name = \"m\"\nform = \"two_step\"\nparameters = \"h = 0.1; a = 2\"\n";
  const auto expect = [](const std::string& got, const std::string& where, const std::string& why) {
    EXPECT_NE(got.find(where), std::string::npos) << got;
    EXPECT_NE(got.find(why), std::string::npos) << got;
  };
  // syntax, on the second line of the step
  expect(error_of(two_step + "step = \"\"\"\nq1_next = a*q1 - q1_prev\nq2_next = q2 +* a\n\"\"\""),
         "test.toml:5: [map] step: line 2, column 15", "expected a number, a name or");
  // an unknown symbol, where it is written
  expect(error_of(two_step + "step = \"q1_next = a*q1 - q1_prev; q2_next = b*q2\""),
         "[map] step: line 1, column 37", "unknown symbol 'b'");
  // a parameter declared and unused; a parameter given that the map lacks
  expect(error_of(two_step + "step = \"q1_next = q1 - q1_prev; q2_next = q2\""), "[map] parameters",
         "'a' is declared but no formula uses it");
  expect(error_of(two_step + "step = \"q1_next = a*q1 - q1_prev; q2_next = q2\"\nb = 1"), "[map]",
         "map 'm' has no parameter 'b' (its parameters: h a)");
  // a division by a parameter that is 0, at its default or as given
  expect(error_of("name = \"m\"\nform = \"phase\"\nparameters = \"c = 0\"\nstep = \"p1 = p1 - q1/c\""),
         "[map] step: line 1, column 13", "division by zero");
  expect(error_of("name = \"m\"\nform = \"phase\"\nparameters = \"c = 1\"\nstep = \"p1 = p1 - q1/c\"\n"
                  "c = 0"),
         "[map] step: line 1, column 13", "division by zero");
  // too long, too deep
  std::string long_step;  // lines within TOML's, 20000 characters in all
  while (long_step.size() < 20000) long_step += "p1 = p1 + 1\n";
  expect(error_of("name = \"m\"\nform = \"phase\"\nstep = \"\"\"\n" + long_step + "\"\"\""),
         "[map] step", "at most 16384");
  expect(error_of("name = \"m\"\nform = \"phase\"\nstep = \"p1 = " + std::string(100, '(') + "q1" +
                  std::string(100, ')') + "\""),
         "[map] step: line 1", "deep");
  // equations not linear in q_{n+1}
  expect(error_of(two_step + "equations = \"\"\"\neq1 = a*q1_next - q1\neq2 = q2_next*q1_next - q2\n\"\"\""),
         "[map] equations: line 2, column 14", "not linear in q1_next, q2_next");
  // the forms' keys
  expect(error_of("name = \"m\"\nform = \"three_step\"\nstep = \"p1 = q1\""), "[map] form",
         "not a form");
  expect(error_of("name = \"m\"\nform = \"two_step\"\nparameters = \"a = 2\"\n"
                  "step = \"q1_next = a*q1 - q1_prev; q2_next = q2\""),
         "[map] momentum", "needs a parameter h");
  expect(error_of(two_step + "step = \"q1_next = a*q1 - q1_prev\""), "[map] step",
         "assigns no 'q2_next'");
}

// Both models from the same points; true when every state component agrees byte for byte.
struct Runs {
  std::unique_ptr<Model> built_in, formulas;
};
std::string first_difference(const Ensemble& a, const Ensemble& b) {
  for (std::size_t i = 0; i < a.orbits; ++i) {
    for (std::size_t k = 0; k < a.state.size(); ++k)
      if (std::bit_cast<std::uint64_t>(a.state[k][i]) != std::bit_cast<std::uint64_t>(b.state[k][i]))
        return "state " + std::to_string(k) + " of orbit " + std::to_string(i);
    for (std::size_t k = 0; k < a.columns.size(); ++k)
      if (std::memcmp(&a.columns[k][i], &b.columns[k][i], sizeof(double)) != 0)
        return a.column_specs[k].path + " of orbit " + std::to_string(i);
    if (a.escape_step[i] != b.escape_step[i] || a.escape_reason[i] != b.escape_reason[i])
      return "the escape of orbit " + std::to_string(i);
  }
  return "";
}

TEST(FormulaMap, SurisAsFormulasIsTheBuiltInMapByteForByteOnEveryPath) {
  const auto formulas = definition_of(preset("suris-formulas"));
  const auto isas = testing::isas_to_run();
  struct Case {
    ParamValues params;
    double q, p, bound;
  };
  for (const Case& k : {Case{{}, 0.5, 0.5, 1e8}, Case{{{"alpha", -0.4}}, 1.2, 1.0, 10.0}})
    for (int deviations : {0, 1, 9}) {
      SCOPED_TRACE("alpha " + std::to_string(k.params.count("alpha") ? -0.4 : 0.9) + ", " +
                   std::to_string(deviations) + " deviations");
      ParamValues params = {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}};
      for (const auto& [name, value] : k.params) params[name] = value;
      const ChaosOptions chaos{deviations == 9, 3};
      const auto built_in = deviations ? make_model("suris", params, chaos) : make_model("suris", params);
      const auto written = deviations ? make_model(formulas, params, chaos) : make_model(formulas, params);
      ASSERT_EQ(written->invariant_names(), built_in->invariant_names());
      RunPlan plan;
      plan.total = plan.last = 400;
      plan.stride = 7;
      plan.escape_bound = k.bound;
      const auto points = testing::box_points(1001, k.q, k.p);
      const auto start = [&](const Model& m) {
        Ensemble e = m.ensemble(points.size());
        m.start_at(e, 0, points, Start::taylor, k.bound);
        e.fill_padding();
        return e;
      };
      Ensemble reference = start(*built_in);
      built_in->advance(reference, plan, Execution{Isa::scalar, 1, 1});
      if (k.bound < 100) {
        EXPECT_GT(reference.escaped(), 100u) << "the escapes are exercised";
      }
      std::vector<Isa> paths = {Isa::scalar};
      paths.insert(paths.end(), isas.begin(), isas.end());
      for (Isa isa : paths) {  // 1 chain asked: blocks of 8 run (ChainRange), as for any count
        Ensemble e = start(*written);
        written->advance(e, plan, Execution{isa, 2, 1});
        EXPECT_EQ(first_difference(reference, e), "") << isa_name(isa);
      }
      // the phase points and invariants the file writes
      Ensemble e = start(*written);
      written->advance(e, plan, Execution{Isa::scalar, 1, 1});
      for (std::size_t i = 0; i < 1001; i += 97) {
        const Phase x = built_in->phase(reference, i), y = written->phase(e, i);
        EXPECT_EQ(std::memcmp(&x, &y, sizeof x), 0) << "orbit " << i;
        EXPECT_EQ(built_in->invariants(reference, i), written->invariants(e, i));
        EXPECT_EQ(built_in->indicators(reference, i).size(), written->indicators(e, i).size());
      }
    }
}

// Suris written naturally (a·b + c, two roundings each) and as the equations linear in q_{n+1}
// that its discretization is, solved by Cramer's rule.
const std::string suris_natural = R"(name = "suris-natural"
form = "two_step"
parameters = "A = 0.7; B = 0.3; alpha = 0.9; h = 0.1"
step = """
D = 1 + 2*alpha*h^2*(q1^2 + q2^2)
q1_next = 2*(1 - A*h^2)*q1/D - q1_prev
q2_next = 2*(1 - B*h^2)*q2/D - q2_prev
"""
)";
const std::string suris_equations = R"(name = "suris-equations"
form = "two_step"
parameters = "A = 0.7; B = 0.3; alpha = 0.9; h = 0.1"
equations = """
D = 1 + 2*alpha*h^2*(q1^2 + q2^2)
eq1 = (q1_next + q1_prev)*D - 2*(1 - A*h^2)*q1
eq2 = (q2_next + q2_prev)*D - 2*(1 - B*h^2)*q2
"""
)";

// The same map computed with other roundings: orbits agree to 1e-12 over 100 steps, and then
// drift apart only by the phase their tiny difference in frequency accumulates (1e-10 after 10⁴
// steps); along them, the built-in map's invariants H, I1, I2 keep within its own drift bound.
TEST(FormulaMap, SurisWrittenNaturallyOrAsEquationsAgreesWithTheBuiltInMap) {
  constexpr double other_roundings = 1e-12;  // relative, over 100 steps: the algebra differs
  constexpr double phase_drift = 1e-9;       // relative, over 10⁴ steps
  const double drift_bound = kernels::Suris::facts.drift_tolerance;  // relative, 10⁴ steps
  const auto built_in =
      make_model("suris", {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}});
  for (const std::string& text : {suris_natural, suris_equations}) {
    const auto written = map_of(Config::parse("[map]\n" + text, "test.toml"));
    const auto points = testing::box_points(64, 0.5, 0.5);
    Ensemble a = built_in->start(points, Start::taylor, 1e8);
    Ensemble b = written->start(points, Start::euler, 1e8);
    for (std::size_t i = 0; i < points.size(); ++i)  // the same first states
      for (std::size_t k = 0; k < 4; ++k) b.state[k][i] = a.state[k][i];
    std::vector<std::vector<double>> initial;
    for (std::size_t i = 0; i < points.size(); ++i) initial.push_back(built_in->invariants(a, i));
    for (const auto& [steps, bound] : {std::pair{100LL, other_roundings}, {10000LL, phase_drift}}) {
      RunPlan plan;
      plan.total = 10000;
      plan.first = a.step;
      plan.last = steps;
      plan.escape_bound = 1e8;
      built_in->advance(a, plan, Execution{Isa::scalar, 1, 1});
      written->advance(b, plan, Execution{Isa::scalar, 1, 1});
      double worst = 0, drift = 0;
      for (std::size_t i = 0; i < points.size(); ++i) {
        double scale = 0;
        for (std::size_t k = 0; k < 4; ++k) scale = std::max(scale, std::fabs(a.state[k][i]));
        for (std::size_t k = 0; k < 4; ++k)
          worst = std::max(worst, std::fabs(a.state[k][i] - b.state[k][i]) / scale);
        std::vector<double> state(4);
        for (std::size_t k = 0; k < 4; ++k) state[k] = b.state[k][i];
        const auto now = built_in->invariants_of(state);
        for (std::size_t k = 0; k < now.size(); ++k)
          drift = std::max(drift, std::fabs(now[k] - initial[i][k]) / std::fabs(initial[i][0]));
      }
      std::cout << written->name() << " after " << steps << " steps: state " << worst
                << ", the built-in invariants' drift " << drift << "\n";
      EXPECT_LT(worst, bound) << written->name() << " after " << steps;
      EXPECT_LT(drift, drift_bound) << written->name() << " after " << steps;
    }
    EXPECT_EQ(b.escaped(), 0u);
  }
}

TEST(FormulaMap, ASingularSystemIsThatOrbitsFault) {
  const auto model = map_of(Config::parse(R"([map]
name = "singular"
form = "two_step"
parameters = "h = 0.1"
equations = "eq1 = q1*q1_next - 1; eq2 = q2_next - q2"
)", "test.toml"));
  Ensemble e = model->ensemble(2);
  model->start_from_state(e, std::vector<std::vector<double>>{{1, 1}, {1, 1}, {0.5, 0.0}, {1, 1}},
                          1e8);
  RunPlan plan;
  plan.total = plan.last = 3;
  plan.escape_bound = 1e8;
  model->advance(e, plan, Execution{Isa::scalar, 1, 1});
  EXPECT_EQ(e.escape_step[0], -1);
  EXPECT_EQ(e.escape_reason[1], static_cast<std::uint8_t>(EscapeReason::singular));
  EXPECT_EQ(escape_reason_name(EscapeReason::singular), "linear equations singular");
}

// The Jacobian of one step: from the step on duals, and by central differences of the step in
// long double (step 1e-6).
struct Jacobians {
  double dual[4][4], central[4][4], norm = 0;
};
Jacobians jacobians(const Formula::Coeffs& c, const Formula::State<double>& s) {
  Jacobians j;
  using D = Dual<double, 4>;
  Formula::State<D> x;
  for (std::size_t k = 0; k < 4; ++k) {
    x[k] = D(s[k], {});
    x[k].d[k] = 1;
  }
  Formula::step(c, x);
  const long double h = 1e-6L;
  for (std::size_t k = 0; k < 4; ++k) {
    Formula::State<long double> up, down;
    for (std::size_t i = 0; i < 4; ++i) up[i] = down[i] = s[i];
    up[k] += h;
    down[k] -= h;
    Formula::step(c, up);
    Formula::step(c, down);
    for (std::size_t i = 0; i < 4; ++i) {
      j.dual[i][k] = x[i].d[k];
      j.central[i][k] = static_cast<double>((up[i] - down[i]) / (2 * h));
      j.norm = std::max(j.norm, std::fabs(j.central[i][k]));
    }
  }
  return j;
}

double determinant(const double (&m)[4][4]) {
  long double a[4][4], det = 1;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) a[i][k] = m[i][k];
  for (int c = 0; c < 4; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[pivot][c])) pivot = r;
    if (pivot != c) {
      std::swap(a[pivot], a[c]);
      det = -det;
    }
    det *= a[c][c];
    for (int r = c + 1; r < 4; ++r)
      for (int k = 4; k-- > c;) a[r][k] -= a[r][c] / a[c][c] * a[c][k];
  }
  return static_cast<double>(det);
}

TEST(FormulaMap, TangentAgreesWithCentralDifferencesAndIsSymplectic) {
  constexpr double tangent_vs_central_difference = 1e-8;  // relative to the Jacobian's norm
  constexpr double det_round_off = 1e-13;
  for (const char* name : {"suris-formulas", "suris-kicked", "froeschle", "henon-heiles"}) {
    SCOPED_TRACE(name);
    const auto d = definition_of(preset(name));
    const auto values = resolve_params(d->text().name, d->params(), {});
    const Formula::Coeffs c = Formula::coefficients(values, d);
    for (const auto& x : testing::box_points(20, 0.4, 0.3)) {
      const auto s = Formula::from_phase_space(c, x, Start::taylor);
      const Jacobians j = jacobians(c, s);
      for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k)
          EXPECT_LT(std::fabs(j.dual[r][k] - j.central[r][k]), tangent_vs_central_difference * j.norm)
              << "d x" << r << " / d x" << k;
      EXPECT_NEAR(determinant(j.dual), 1.0, det_round_off);
    }
  }
}

TEST(FormulaMap, ChainsSteppedTogetherWithTheStateResidentGiveTheSingleStepsBytes) {
  // K chains of a batch, many steps in one call (the state kept in the register file, rotating
  // through its slots, where the step allows: resident), against each lane's scalar steps one at a
  // time; and the escape measures summed on the way, against the chains' own.
  using V = xsimd::batch<double>;
  constexpr int K = 3;
  constexpr std::size_t W = V::size;
  const std::vector<std::pair<std::string, bool>> maps = {  // preset, resident
      {"suris-formulas", true}, {"suris-kicked", true}, {"froeschle", true},
      {"henon-heiles", true}, {"mcmillan", false}};  // (McMillan's q' = p: an output of no instruction)
  for (const auto& [name, resident] : maps) {
    const auto d = definition_of(preset(name));
    const Formula::Coeffs c = Formula::coefficients(resolve_params(d->text().name, d->params(), {}), d);
    EXPECT_EQ(!c.program->resident.programs.empty(), resident) << name;
    const auto points = testing::box_points(K * W, 0.4, 0.3);
    for (const long long steps : {1LL, 2LL, 3LL, 5LL, 64LL}) {
      Formula::State<V> s[K];
      std::vector<Formula::State<double>> one(points.size());
      for (std::size_t k = 0; k < K; ++k)
        for (std::size_t i = 0; i < 4; ++i) {
          alignas(64) double lanes[W];
          for (std::size_t w = 0; w < W; ++w) {
            one[k * W + w] = Formula::from_phase_space(c, points[k * W + w], Start::taylor);
            lanes[w] = one[k * W + w][i];
          }
          s[k][i] = V::load_aligned(lanes);
        }
      V escape(0.0);
      Formula::step_chains<V, K>(c, s, steps, escape);
      double escape_one = 0;
      for (std::size_t k = 0; k < K; ++k)
        for (std::size_t w = 0; w < W; ++w) {
          auto& x = one[k * W + w];
          for (long long n = 0; n < steps; ++n) {
            escape_one += Formula::escape_measure(x);
            Formula::step(c, x);
          }
          for (std::size_t i = 0; i < 4; ++i) {
            alignas(64) double lanes[W];
            s[k][i].store_aligned(lanes);
            EXPECT_EQ(std::bit_cast<std::uint64_t>(lanes[w]), std::bit_cast<std::uint64_t>(x[i]))
                << name << ", " << steps << " steps, chain " << k << ", lane " << w;
          }
        }
      // (summed in another order: equal to round-off)
      alignas(64) double sums[W];
      escape.store_aligned(sums);
      double escape_all = 0;
      for (const double x : sums) escape_all += x;
      EXPECT_NEAR(escape_all, escape_one, 1e-12 * escape_one) << name;
    }
  }
}

TEST(FormulaMap, McMillanKeepsItsInvariantToRoundOffWithOneDegreeOfFreedom) {
  constexpr double drift_bound = 1e-13;  // relative, over 10⁵ steps
  const auto model = map_of(preset("mcmillan"));
  ASSERT_EQ(model->invariant_names(), std::vector<std::string>{"I"});
  const auto points = testing::box_points(64, 1.0, 1.0);
  Ensemble e = model->start(points, Start::euler, 1e8);
  std::vector<double> initial(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) initial[i] = model->invariants(e, i)[0];
  RunPlan plan;
  plan.total = plan.last = 100000;
  plan.escape_bound = 1e8;
  model->advance(e, plan, Execution{Isa::scalar, 1, 1});
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_LT(std::fabs(model->invariants(e, i)[0] - initial[i]), drift_bound * std::fabs(initial[i]) + 1e-15);
    const Phase x = model->phase(e, i);
    EXPECT_EQ(x.q2, points[i].q2);  // the second degree of freedom stays as it was
    EXPECT_EQ(x.p2, points[i].p2);
  }
}

}  // namespace
}  // namespace qmaps
