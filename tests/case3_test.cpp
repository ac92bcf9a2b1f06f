// case3's quartic solver: every root it returns is the root of the scheme, refined independently
// in long double from the equation itself (not the kernel's expanded quartic), to round-off; a
// start that crosses the barrier of an attractive quartic escapes with the solver's reason, at the
// same step on every path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/isa.hpp"
#include "ensemble_fixtures.hpp"
#include "kernels/case3.hpp"

namespace qmaps {
namespace {

using kernels::Case3;

// The scheme times c for one component, (w − 2u + v) − c(2λu − 2Au³(w² + wv + v²)
// − 2αu⁵(w⁴ + w³v + w²v² + wv³ + v⁴)), and its w-derivative, in long double.
struct Scheme {
  long double A, alpha, c, lambda, u, v;
  long double residual(long double w) const {
    const long double u3 = u * u * u, u5 = u3 * u * u;
    const long double s2 = w * w + w * v + v * v;
    const long double s4 = w * w * w * w + w * w * w * v + w * w * v * v + w * v * v * v + v * v * v * v;
    return (w - 2 * u + v) - c * (2 * lambda * u - 2 * A * u3 * s2 - 2 * alpha * u5 * s4);
  }
  long double slope(long double w) const {
    const long double u3 = u * u * u, u5 = u3 * u * u;
    const long double d4 = 4 * w * w * w + 3 * w * w * v + 2 * w * v * v + v * v * v;
    return 1 + c * (2 * A * u3 * (2 * w + v) + 2 * alpha * u5 * d4);
  }
  long double root_near(long double w) const {
    for (int i = 0; i < 4; ++i) w -= residual(w) / slope(w);
    return w;
  }
};

TEST(Case3Solver, RootsAreTheSchemesRootToRoundOffWithinTolerance) {
  for (const double ds : {0.05, 0.1, 0.15}) {
    const double A = 0.7, alpha = 0.9;
    const double p[] = {A, alpha, ds, 2};
    const auto c = Case3::coefficients(p);
    double worst = 0;
    long long steps = 0;
    for (const Phase& x : testing::box_points(256, 0.5, 0.5)) {
      auto s = Case3::from_phase_space(c, x, Start::taylor);
      for (int n = 0; n < 200; ++n) {
        const auto before = s;
        ASSERT_EQ(Case3::step(c, s), 0.0) << "ds " << ds << " step " << n;
        for (int k = 0; k < 2; ++k) {
          const Scheme scheme{A, alpha, c.c, before[6], before[2 + k], before[k]};
          const long double exact = scheme.root_near(s[2 + k]);
          const double units = std::fabs(static_cast<double>(exact - s[2 + k])) /
                               (0x1p-53 * (1 + std::fabs(s[2 + k])));
          worst = std::max(worst, units);
        }
        ++steps;
      }
    }
    std::printf("[ root ] case3 ds %.2f: %lld steps, max |w - w*| = %.2f x 2^-53 (1 + |w|)\n", ds,
                steps, worst);
    EXPECT_LE(worst, 8.0) << "ds " << ds;
  }
}

TEST(Case3Solver, StartOverTheBarrierEscapesWithTheSolversReasonOnEveryPath) {
  const auto model = make_model("case3", {{"A", 0.7}, {"alpha", -0.9}, {"ds", 0.1}});
  RunPlan plan;
  plan.total = plan.last = 10;
  std::vector<Isa> paths = runnable_isas();
  paths.insert(paths.begin(), Isa::scalar);
  for (const Isa isa : paths) {
    Ensemble e = model->start(std::vector<Phase>{{0.9, -0.2, 0.1, 0.4}}, Start::taylor, 1e8);
    model->advance(e, plan, Execution{isa, 1, 1});
    EXPECT_EQ(e.escape_step[0], 2) << isa_name(isa);
    EXPECT_EQ(e.escape_reason[0], static_cast<std::uint8_t>(EscapeReason::no_convergence))
        << isa_name(isa);
    for (std::size_t k = 0; k < e.state.size(); ++k)
      EXPECT_TRUE(std::isfinite(e.state[k][0])) << isa_name(isa) << " state " << k;
  }
}

}  // namespace
}  // namespace qmaps
