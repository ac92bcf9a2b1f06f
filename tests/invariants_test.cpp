// Invariant conservation of every map over 10⁵ steps through the SIMD runner (invariants sampled
// every step), from random bounded orbits. Two measures per invariant, printed by the test:
// per orbit relative, max_n |I_n − I_0| / |I_0|; and relative to the ensemble's scale,
// |I_n − I_0| / mean |I_0| (robust where an orbit's I_0 is near 0). Bounds are about ten times
// the largest value measured here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/isa.hpp"
#include "ensemble_fixtures.hpp"

namespace qmaps {
namespace {

struct Bound {
  std::string invariant;
  double relative_to_scale;
};

struct Conservation {
  const char* name;
  const char* map;
  ParamValues params;
  std::size_t orbits;
  std::vector<Bound> bounds;
};

const Conservation maps[] = {
    {"suris", "suris", {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}}, 1000,
     {{"H", 1.5e-11}, {"I1", 2e-11}, {"I2", 2e-11}}},
    {"suris_A_eq_B", "suris", {{"A", 0.5}, {"B", 0.5}, {"alpha", 0.9}, {"h", 0.1}}, 500,
     {{"H", 1.5e-11}, {"L", 2e-11}}},
    {"case2", "case2", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}}, 500,
     {{"H1", 3e-11}, {"H2", 3e-11}, {"I1", 3e-11}, {"I2", 3e-11}}},
    {"case2_staggered", "case2-staggered", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}}, 200,
     {{"H1", 3e-11}, {"H2", 3e-11}, {"I1", 3e-11}, {"I2", 3e-11}}},
    {"case2_hky", "case2-hky",
     {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}, {"c11", 0.37}, {"c12", 0.41}, {"c21", 0.77}, {"c22", 0.19}},
     500, {{"K+", 3e-11}, {"K-", 3e-11}, {"I1", 3e-11}, {"I2", 3e-11}}},
    {"case3", "case3", {{"A", 0.7}, {"alpha", 0.9}, {"ds", 0.1}}, 200, {{"I_1", 1e-10}, {"I_2", 1e-10}}},
};

void PrintTo(const Conservation& c, std::ostream* os) { *os << c.name; }

class Invariants : public ::testing::TestWithParam<Conservation> {};

TEST_P(Invariants, DriftOverHundredThousandStepsStaysAtRoundOff) {
  const Conservation& m = GetParam();
  const auto model = make_model(m.map, m.params);
  RunPlan plan;
  plan.total = plan.last = 100000;
  Ensemble e = model->start(testing::box_points(m.orbits, 0.5, 0.5, 2024), Start::taylor, 1e8);
  model->advance(e, plan, Execution{best_isa(), 2, 4});
  ASSERT_EQ(e.escaped(), 0u);
  const auto& names = model->invariant_names();
  ASSERT_EQ(names.size(), m.bounds.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    EXPECT_EQ(names[k], m.bounds[k].invariant);
    double scale = 0;
    for (std::size_t i = 0; i < e.orbits; ++i) scale += std::fabs(e.invariant_initial[k][i]);
    scale /= static_cast<double>(e.orbits);
    std::vector<double> per_orbit(e.orbits), to_scale(e.orbits);
    for (std::size_t i = 0; i < e.orbits; ++i) {
      per_orbit[i] = e.invariant_max_drift[k][i] / std::fabs(e.invariant_initial[k][i]);
      to_scale[i] = e.invariant_max_drift[k][i] / scale;
    }
    std::sort(per_orbit.begin(), per_orbit.end());
    std::sort(to_scale.begin(), to_scale.end());
    const std::size_t n = e.orbits;
    std::printf("[ drift ] %-16s %-3s per orbit: median %.1e p99 %.1e max %.1e | to scale: median "
                "%.1e max %.1e (bound %.1e)\n",
                m.name, names[k].c_str(), per_orbit[n / 2], per_orbit[n * 99 / 100],
                per_orbit.back(), to_scale[n / 2], to_scale.back(), m.bounds[k].relative_to_scale);
    EXPECT_LT(to_scale.back(), m.bounds[k].relative_to_scale) << names[k];
    EXPECT_GT(to_scale.back(), 0.0) << names[k] << ": zero drift means nothing was tracked";
  }
}

INSTANTIATE_TEST_SUITE_P(Maps, Invariants, ::testing::ValuesIn(maps),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Invariants, SurisSumOfI1AndI2EqualsTwoHSquaredTimesHWithinTolerance) {
  const auto model = testing::suris();
  const auto points = testing::box_points(200, 0.5, 0.5, 5);
  RunPlan plan;
  plan.total = plan.last = 1000;
  Ensemble e = model->start(points, Start::taylor, plan.escape_bound);
  model->advance(e, plan, Execution{});
  const double h = 0.1;
  for (std::size_t i = 0; i < e.orbits; ++i) {
    const auto v = model->invariants(e, i);  // H, I1, I2
    EXPECT_NEAR(v[1] + v[2], 2 * h * h * v[0], 1e-16 + 4e-15 * std::fabs(v[0]) * h * h) << i;
  }
}

}  // namespace
}  // namespace qmaps
