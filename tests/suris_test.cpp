// The Suris kernel's contract: parameter validation, invariant names, the start rules and the
// conversion back to phase space, reversibility.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "ensemble_fixtures.hpp"
#include "kernels/suris.hpp"

namespace qmaps {
namespace {

using kernels::Suris;

void expect_usage_error(const ParamValues& p, const std::string& fragment) {
  try {
    testing::suris();  // a valid set still builds
    make_model("suris", p);
    ADD_FAILURE() << "accepted: " << fragment;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::usage);
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Suris, RejectsInvalidParametersNamingTheProblem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  expect_usage_error({{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}}, "'h' is missing");
  expect_usage_error({{"A", 0.7}, {"B", 0.3}, {"alpha", nan}, {"h", 0.1}}, "'alpha' must be finite");
  expect_usage_error({{"A", inf}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}}, "'A' must be finite");
  expect_usage_error({{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.0}}, "h must be > 0");
  expect_usage_error({{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", -0.1}}, "h must be > 0");
  expect_usage_error({{"A", 1.0}, {"B", 0.3}, {"alpha", 0.9}, {"h", 1.0}}, "1 - A h^2 = 0");
  expect_usage_error({{"A", 0.7}, {"B", 4.0}, {"alpha", 0.9}, {"h", 0.5}}, "1 - B h^2 = 0");
  expect_usage_error({{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}, {"beta", 1}},
                     "no parameter 'beta'");
  expect_usage_error({}, "missing");
}

// Where (1 − Ah²)² − (1 − Bh²)² rounds to 0 with A ≠ B, I1 and I2 would divide by zero (every
// orbit's I1 NaN): such parameters are refused; A = B (H and L) stays valid at any h.
TEST(Suris, RefusesParametersWhereI1AndI2CannotBeEvaluated) {
  const std::string rule = "I1 and I2 divide by it";
  expect_usage_error({{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 1e-9}}, rule);
  expect_usage_error({{"A", 0.7}, {"B", std::nextafter(0.7, 1.0)}, {"alpha", 0.9}, {"h", 0.1}},
                     rule);
  expect_usage_error({{"A", 0.5}, {"B", 1.5}, {"alpha", 0.9}, {"h", 1.0}}, rule);  // a = −b
  expect_usage_error({{"A", 0.7}, {"B", 0.3}, {"alpha", 1e308}, {"h", 1.0}}, "overflow");
  EXPECT_NO_THROW(make_model("suris", {{"A", 0.7}, {"B", 0.7}, {"alpha", 0.9}, {"h", 1e-9}}));
  EXPECT_NO_THROW(make_model("suris", {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 1e-7}}));
}

TEST(Suris, UnknownMapIsUsageErrorListingKnownMaps) {
  try {
    make_model("surix", {});
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("known maps: suris"), std::string::npos) << e.what();
  }
}

TEST(Suris, I1AndI2WhenAAndBDifferElseAngularMomentumL) {
  EXPECT_EQ(testing::suris(0.7, 0.3)->invariant_names(), (std::vector<std::string>{"H", "I1", "I2"}));
  EXPECT_EQ(testing::suris(0.5, 0.5)->invariant_names(), (std::vector<std::string>{"H", "L"}));
}

TEST(Suris, StartRulesAreExactlyThoseOfMapsMd) {
  const auto c = Suris::coefficients(std::array{0.7, 0.3, 0.9, 0.1});
  const Phase x{0.3, -0.2, 0.1, 0.4};
  const auto euler = Suris::from_phase_space(c, x, Start::euler);
  EXPECT_EQ(euler[2], 0.3 + 0.1 * 0.1);
  EXPECT_EQ(euler[3], -0.2 + 0.1 * 0.4);
  const auto taylor = Suris::from_phase_space(c, x, Start::taylor);
  const double r2 = 0.3 * 0.3 + 0.2 * 0.2;
  EXPECT_EQ(taylor[2], (0.3 + 0.1 * 0.1) + 0.5 * 0.1 * 0.1 * (-2 * 0.7 * 0.3 - 4 * 0.9 * 0.3 * r2));
  EXPECT_EQ(taylor[0], 0.3);
}

TEST(Suris, PhaseSpaceRoundTripRecoversMomentumToAtLeastSecondOrderWithinTolerance) {
  // The central difference recovers p with an error of order ≥ 2 (measured: 3, halving h
  // divides it by 8).
  double previous = 0;
  for (double h : {0.1, 0.05, 0.025}) {
    const auto c = Suris::coefficients(std::array{0.7, 0.3, 0.9, h});
    const Phase x{0.3, -0.2, 0.1, 0.4};
    const Phase back = Suris::to_phase_space(c, Suris::from_phase_space(c, x, Start::taylor));
    EXPECT_EQ(back.q1, x.q1);
    EXPECT_EQ(back.q2, x.q2);
    const double err = std::hypot(back.p1 - x.p1, back.p2 - x.p2);
    EXPECT_LT(err, 0.05 * h * h);
    if (previous > 0) {
      EXPECT_GT(previous / err, 3.5) << "h = " << h;
    }
    previous = err;
  }
}

TEST(Suris, ReversedRunReturnsToStartWithinTolerance) {
  const auto c = Suris::coefficients(std::array{0.7, 0.3, 0.9, 0.1});
  const auto s0 = Suris::from_phase_space(c, {0.5, 0.1, -0.3, 0.2}, Start::taylor);
  auto s = s0;
  for (int n = 0; n < 1000; ++n) Suris::step(c, s);
  s = {s[2], s[3], s[0], s[1]};
  for (int n = 0; n < 1000; ++n) Suris::step(c, s);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(s[k], s0[(k + 2) % 4], 1e-12) << k;
}

TEST(Suris, PhysicalTimeIsStepTimesH) {
  const auto model = testing::suris();
  Ensemble e = model->start(testing::box_points(3, 0.5, 0.5), Start::taylor, 1e8);
  RunPlan plan;
  plan.total = plan.last = 250;
  model->advance(e, plan, Execution{});
  EXPECT_FALSE(model->time_per_orbit());
  EXPECT_EQ(model->time(e, 2), 250 * 0.1);
}

}  // namespace
}  // namespace qmaps
