// Independent references for the Suris kernel, all tolerance checks:
//  - the same kernel template at V = long double (64-bit significand) follows the double path
//    within a stated tolerance over 1000 steps, and conserves H, I1, I2 far better;
//  - discretization (a), solved as its 2×2 linear system (docs/maps.md §3), gives the Suris update;
//  - the invariants in their well-conditioned form equal the literal formulas of docs/maps.md §3.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "kernels/suris.hpp"

namespace qmaps {
namespace {

using kernels::Suris;
const auto c = Suris::coefficients(std::array{0.7, 0.3, 0.9, 0.1});
const std::array<Phase, 3> starts = {{{0.3, -0.2, 0.1, 0.4}, {0.5, 0.1, -0.3, 0.2}, {-0.1, 0.45, 0.25, -0.15}}};

template <class T>
Suris::State<T> cast(const Suris::State<double>& s) {
  return {T(s[0]), T(s[1]), T(s[2]), T(s[3])};
}

TEST(Reference, DoublePathFollowsLongDoublePathWithinToleranceOverThousandSteps) {
  for (const auto& x : starts) {
    auto d = Suris::from_phase_space(c, x, Start::taylor);
    auto ld = cast<long double>(d);
    long double inv0[3] = {}, inv[3] = {};
    Suris::invariants(c, ld, inv0);
    long double worst_invariant = 0;
    double worst_state = 0;
    for (int n = 0; n < 1000; ++n) {
      Suris::step(c, d);
      Suris::step(c, ld);
      for (int k = 0; k < 4; ++k)
        worst_state = std::max(worst_state, std::fabs(d[k] - static_cast<double>(ld[k])));
      Suris::invariants(c, ld, inv);
      for (int k = 0; k < 3; ++k)
        worst_invariant = std::max(worst_invariant, std::fabs((inv[k] - inv0[k]) / inv0[k]));
    }
    EXPECT_LT(worst_state, 1e-12) << "double vs long double state";
    EXPECT_LT(worst_invariant, 5e-16L) << "long double invariant drift";
    std::printf("[ reference ] |q_double - q_longdouble| <= %.2e, long double relative drift %.2Le\n",
                worst_state, worst_invariant);
  }
}

TEST(Reference, DiscretizationASolvedAsLinearSystemGivesSurisUpdateWithinTolerance) {
  const long double h2 = 0.01L, a = 1 - 0.7L * h2, b = 1 - 0.3L * h2, g = 2 * 0.9L * h2, r = a / b;
  for (const auto& x : starts) {
    auto s = Suris::from_phase_space(c, x, Start::taylor);
    for (int n = 0; n < 100; ++n) {
      const long double x1 = s[0], x2 = s[1], y1 = s[2], y2 = s[3];
      // (1 + g y1²) S1 + g r y1 y2 S2 = 2a y1;  g y1 y2 / r S1 + (1 + g y2²) S2 = 2b y2
      const long double m11 = 1 + g * y1 * y1, m12 = g * r * y1 * y2, m21 = g * y1 * y2 / r,
                        m22 = 1 + g * y2 * y2, r1 = 2 * a * y1, r2 = 2 * b * y2;
      const long double det = m11 * m22 - m12 * m21;
      const long double z1 = (r1 * m22 - m12 * r2) / det - x1, z2 = (m11 * r2 - m21 * r1) / det - x2;
      Suris::step(c, s);
      EXPECT_NEAR(s[2], static_cast<double>(z1), 4e-16) << "step " << n;
      EXPECT_NEAR(s[3], static_cast<double>(z2), 4e-16) << "step " << n;
    }
  }
}

TEST(Reference, InvariantsEqualLiteralFormulasOfMapsMdWithinTolerance) {
  const long double A = 0.7L, B = 0.3L, al = 0.9L, h = 0.1L, h2 = h * h;
  const long double a = 1 - A * h2, b = 1 - B * h2, g = 2 * al * h2;
  for (const auto& x : starts) {
    const auto s = Suris::from_phase_space(c, x, Start::taylor);
    const long double u1 = s[0], u2 = s[1], v1 = s[2], v2 = s[3];
    const long double p1 = (v1 - u1) / h, p2 = (v2 - u2) / h;
    const long double H = (p1 * p1 + p2 * p2) / 2 + A * u1 * v1 + B * u2 * v2 +
                          al * (u1 * u1 * v1 * v1 + u2 * u2 * v2 * v2 + u1 * u1 * v2 * v2 +
                                u2 * u2 * v1 * v1);
    const long double I1 = v1 * v1 + u1 * u1 - 2 * a * u1 * v1 + g * u1 * u1 * v1 * v1 +
                           g / (a * a - b * b) *
                               (a * a * (v1 * v1 * u2 * u2 + u1 * u1 * v2 * v2) -
                                2 * a * b * u1 * u2 * v1 * v2);
    const long double I2 = v2 * v2 + u2 * u2 - 2 * b * u2 * v2 + g * u2 * u2 * v2 * v2 +
                           g / (b * b - a * a) *
                               (b * b * (v2 * v2 * u1 * u1 + u2 * u2 * v1 * v1) -
                                2 * a * b * u1 * u2 * v1 * v2);
    double got[3];
    Suris::invariants(c, s, got);
    EXPECT_NEAR(got[0], static_cast<double>(H), 1e-15 * std::fabs(static_cast<double>(H)));
    EXPECT_NEAR(got[1], static_cast<double>(I1), 1e-13 * std::fabs(static_cast<double>(I1)));
    EXPECT_NEAR(got[2], static_cast<double>(I2), 1e-13 * std::fabs(static_cast<double>(I2)));
  }
}

}  // namespace
}  // namespace qmaps
