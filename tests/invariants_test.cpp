// Invariant conservation of the Suris map over 10⁵ steps at h = 0.1, from 1000 random bounded
// orbits: the relative drift max_n |I_n − I_0| / |I_0| of H, I1 and I2 stays at round-off. The
// bounds are about ten times the largest drift measured (printed by the test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/isa.hpp"
#include "ensemble_fixtures.hpp"

namespace qmaps {
namespace {

struct Spread {
  double median, p99, max;
};

Spread spread(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  return {x[x.size() / 2], x[x.size() * 99 / 100], x.back()};
}

TEST(Invariants, RelativeDriftOverHundredThousandStepsStaysAtRoundOff) {
  const auto model = testing::suris();
  const auto points = testing::box_points(1000, 0.5, 0.5, 2024);
  RunPlan plan;
  plan.total = plan.last = 100000;
  plan.stride = 1;
  Ensemble e = model->start(points, Start::taylor, plan.escape_bound);
  model->advance(e, plan, Execution{best_isa(), 2, 4});
  ASSERT_EQ(e.escaped(), 0u);

  // bound = ~10× the largest relative drift measured on this ensemble
  const std::vector<std::pair<std::string, double>> bounds = {
      {"H", 1.5e-11}, {"I1", 2e-11}, {"I2", 2e-11}};
  const auto& names = model->invariant_names();
  ASSERT_EQ(names.size(), bounds.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    EXPECT_EQ(names[k], bounds[k].first);
    std::vector<double> relative(e.orbits);
    for (std::size_t i = 0; i < e.orbits; ++i)
      relative[i] = e.invariant_max_drift[k][i] / std::fabs(e.invariant_initial[k][i]);
    const Spread s = spread(relative);
    std::printf("[ drift ] %-2s relative: median %.2e  p99 %.2e  max %.2e  (bound %.1e)\n",
                names[k].c_str(), s.median, s.p99, s.max, bounds[k].second);
    EXPECT_LT(s.max, bounds[k].second) << names[k];
    EXPECT_GT(s.max, 0.0) << names[k] << ": drift exactly zero means nothing was tracked";
  }
}

TEST(Invariants, SumOfI1AndI2EqualsTwoHSquaredTimesHWithinTolerance) {
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
