// The chaos indicators of core/chaos.hpp (tangent map, λ_max, FLI, MEGNO, the spectrum, GALI),
// recorded by each map's chaos model (core/tangent_map.hpp):
// - on the bounded orbits of the integrable maps, over 10⁵ steps, ⟨Y⟩ → 2 and λ_n decays like
//   ln(n)/n;
// - on the flow at non-integrable parameters (β = α, δ = 12α: a homogeneous quartic with a
//   chaotic sea), λ_n stays positive and ⟨Y⟩ grows linearly, as λ n / 2;
// - where det J = 1 the spectrum sums to 0 in ± pairs; GALI_2 stays up on tori and collapses on
//   chaotic orbits;
// - the chaos model's orbit is the plain map's, bit for bit;
// - ops::log, which the indicators use, is within 2 ulp and gives a batch's lanes the scalar bits.
// (Every path's bits for the chaos records: tests/agreement_test.cpp.)
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <cstdio>
#include <string>
#include <vector>

#include "core/observers/invariants/invariant_columns.hpp"
#include "core/ops.hpp"
#include "kernels/catalogue.hpp"
#include "kernels/maps.hpp"

namespace qmaps {
namespace {

struct Indicators {
  double lyapunov, fli, megno;
  std::array<double, 4> spectrum;
  double gali2, gali4;
};

// The indicators after `steps` steps from x, the spectrum orthonormalized every `every` steps.
Indicators after(std::string_view map, const ParamValues& params, const Phase& x, long long steps,
                 long long every = 1) {
  const auto model = make_model(map, params, ChaosOptions{true, every});
  Ensemble e = model->start(std::span(&x, 1), Start::taylor, 1e8);
  RunPlan plan;
  plan.total = plan.last = steps;
  plan.measure_orbits = false;
  model->advance(e, plan, Execution{});
  EXPECT_LT(e.escape_step[0], 0) << map;
  const auto v = model->indicators(e, 0);
  return {v[0], v[1], v[2], {v[3], v[4], v[5], v[6]}, v[7], v[8]};
}

const ParamValues chaotic_flow = {{"A", 0.0}, {"B", 0.0}, {"alpha", 0.25}, {"beta", 0.25},
                                  {"delta", 3.0}, {"h", 0.05}, {"order", 8}};

// Margins of the integrable maps' indicators at 10⁵ steps. ⟨Y⟩ approaches 2 as 2 − O(ln n/n)
// (measured 1.983 for Suris); λ_n ≤ ln(n)/n (measured 0.65 ln(n)/n).
constexpr double megno_margin = 0.1;

TEST(Chaos, IntegrableMapsHaveMegnoTwoAndLyapunovDecayingAsLogNOverN) {
  for (const MapEntry& m : catalogue()) {
    for (const Phase& x : {Phase{0.3, 0.2, 0.1, 0.25}, Phase{-0.4, 0.1, 0.3, -0.2}}) {
      for (long long n : {10000LL, 100000LL}) {
        const Indicators i = after(m.name, param_values(m.facts->example), x, n, 10);
        const double bound = std::log(static_cast<double>(n)) / static_cast<double>(n);
        EXPECT_LE(std::fabs(i.lyapunov), bound) << m.name << " n = " << n;
        for (double l : i.spectrum) EXPECT_LE(std::fabs(l), 2 * bound) << m.name << " n = " << n;
        if (n == 100000) {
          EXPECT_NEAR(i.megno, 2.0, megno_margin) << m.name;
          EXPECT_GT(i.gali2, 1e-3) << m.name;  // a torus: GALI_2 does not fall exponentially
          std::printf("[ chaos ] %-16s n = 1e5: lambda = %.2e (ln(n)/n = %.2e), FLI = %.2f, "
                      "<Y> = %.4f, GALI_2 = %.2e, GALI_4 = %.1e\n",
                      std::string(m.name).c_str(), i.lyapunov, bound, i.fli, i.megno, i.gali2,
                      i.gali4);
        }
      }
    }
  }
}

TEST(Chaos, NonIntegrableFlowHasPositiveLyapunovAndMegnoGrowingLinearly) {
  for (const Phase& x : {Phase{0.5, 0.5, 0.3, 0.6}, Phase{1.0, 0.2, 0.0, 0.9}}) {
    const Indicators half = after("flow", chaotic_flow, x, 10000),
                     whole = after("flow", chaotic_flow, x, 20000);
    std::printf("[ chaos ] flow, delta = 12 alpha: lambda = %.4f per step, <Y> %.1f -> %.1f "
                "(lambda n / 2 = %.1f)\n", whole.lyapunov, half.megno, whole.megno,
                whole.lyapunov * 20000 / 2);
    EXPECT_GT(whole.lyapunov, 0.005);
    EXPECT_NEAR(whole.spectrum[0], whole.lyapunov, 0.1 * whole.lyapunov);  // the same λ_1
    // e^{−(λ1 − λ2) n} until the two vectors agree to round-off: far below any torus' value
    EXPECT_LT(whole.gali2, 1e-8);
    std::printf("[ chaos ] flow, delta = 12 alpha: lambda_1 = %.4f, GALI_2 = %.1e, GALI_4 = %.1e\n",
                whole.spectrum[0], whole.gali2, whole.gali4);
    EXPECT_GT(whole.fli, 100.0);
    EXPECT_NEAR(whole.megno / half.megno, 2.0, 0.4);                   // linear growth
    EXPECT_NEAR(whole.megno, whole.lyapunov * 20000 / 2, 0.2 * whole.megno);  // ≈ λ n / 2
  }
}

// det J = 1: each step's Gram–Schmidt norms multiply to 1, so the spectrum sums to 0 to
// round-off on regular and chaotic orbits alike; on a chaotic orbit it comes in ± pairs
// (λ_1 = −λ_4 > 0, λ_2 = −λ_3 ≈ 0), while a regular orbit's four decay like ln(n)/n (the
// integrable maps' test). The maps whose det J is not 1 (MapFacts::volume_preserving;
// docs/chaos.md) are left out.
constexpr double spectrum_sum_tolerance = 1e-12;  // per step, summed over n steps / n

TEST(Chaos, SpectraOfVolumePreservingMapsSumToZeroInPlusMinusPairs) {
  const auto check = [](std::string_view map, const ParamValues& params, const Phase& x,
                        long long every, const std::string& what, bool chaotic) {
    const Indicators i = after(map, params, x, 20000, every);
    const double sum = i.spectrum[0] + i.spectrum[1] + i.spectrum[2] + i.spectrum[3];
    std::printf("[ spectrum ] %-36s %+.3e %+.3e %+.3e %+.3e (sum %.1e)\n", what.c_str(),
                i.spectrum[0], i.spectrum[1], i.spectrum[2], i.spectrum[3], sum);
    EXPECT_LE(std::fabs(sum), spectrum_sum_tolerance) << what;
    if (!chaotic) return;
    EXPECT_NEAR(i.spectrum[0], -i.spectrum[3], 0.05 * i.spectrum[0]) << what;
    EXPECT_NEAR(i.spectrum[1], -i.spectrum[2], 0.05 * i.spectrum[0]) << what;
    EXPECT_LT(std::fabs(i.spectrum[1]), 0.05 * i.spectrum[0]) << what;
  };
  for (const MapEntry& m : catalogue()) {
    if (!m.facts->volume_preserving) continue;
    check(m.name, param_values(m.facts->example), Phase{0.3, 0.2, 0.1, 0.25}, 1,
          std::string(m.name), false);
  }
  // Orthonormalized every step, or every 10 (Benettin's re-orthonormalization every k steps).
  for (long long every : {1LL, 10LL})
    check("flow", chaotic_flow, Phase{0.5, 0.5, 0.3, 0.6}, every,
          "flow, delta = 12 alpha, every " + std::to_string(every), true);
}

// The chaos model steps the state by the map's own step on Dual values, whose values never read
// a derivative: its orbit is the plain map's, bit for bit.
TEST(Chaos, ChaosModelOrbitIsThePlainMapsBitForBit) {
  for (const MapEntry& m : catalogue()) {
    const auto params = param_values(m.facts->example);
    const auto plain = make_model(m.name, params);
    const Phase x{0.3, 0.2, 0.1, 0.25};
    RunPlan plan;
    plan.total = plan.last = 3000;
    Ensemble a = plain->start(std::span(&x, 1), Start::taylor, 1e8);
    plain->advance(a, plan, Execution{});
    for (bool spectrum : {false, true}) {
      const auto chaos = make_model(m.name, params, ChaosOptions{spectrum, 7});
      Ensemble b = chaos->start(std::span(&x, 1), Start::taylor, 1e8);
      chaos->advance(b, plan, Execution{});
      for (std::size_t k = 0; k < plain->state_names().size(); ++k)
        EXPECT_EQ(std::bit_cast<std::uint64_t>(a.state[k][0]),
                  std::bit_cast<std::uint64_t>(b.state[k][0]))
            << m.name << " component " << k << (spectrum ? " (nine deviations)" : "");
      EXPECT_EQ(std::bit_cast<std::uint64_t>(invariant_drift(a, 0)[0]),
                std::bit_cast<std::uint64_t>(invariant_drift(b, 0)[0]))
          << m.name;
    }
  }
}

// ops::log against the C library's over 40 binades, subnormals and the special values; and an
// SSE2 batch (every x86-64 build has it) gives each lane the scalar's bits.
constexpr double log_tolerance_ulp = 2;

TEST(Chaos, LogIsWithinTwoUlpAndTheSameInEveryLane) {
  using B = xsimd::batch<double, xsimd::sse2>;
  std::uint64_t x = 0x9E3779B97F4A7C15ull;
  double worst = 0;
  const auto check = [&](double a, double b) {
    alignas(16) const double two[2] = {a, b};
    const auto lanes = ops::lanes_of(ops::log(B::load_aligned(two)));
    for (int l = 0; l < 2; ++l) {
      const double v = two[l], mine = ops::log(v), libc = std::log(v);
      ASSERT_EQ(std::bit_cast<std::uint64_t>(lanes[static_cast<std::size_t>(l)]),
                std::bit_cast<std::uint64_t>(mine))
          << "log(" << v << "): batch lane differs from the scalar";
      if (std::isnan(libc)) {
        ASSERT_TRUE(std::isnan(mine)) << v;
      } else if (std::isinf(libc) || libc == 0) {
        ASSERT_EQ(mine, libc) << v;
      } else {
        const double ulps = std::fabs(mine - libc) / (std::nextafter(std::fabs(libc), HUGE_VAL) -
                                                      std::fabs(libc));
        worst = std::max(worst, ulps);
        ASSERT_LE(ulps, log_tolerance_ulp) << "log(" << v << ") = " << mine << ", libc " << libc;
      }
    }
  };
  for (int i = 0; i < 200000; ++i) {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    const double m = 1 + static_cast<double>(x >> 11) * 0x1p-53;          // [1, 2)
    const int e = static_cast<int>(x % 80) - 40;
    check(std::ldexp(m, e), 1 + (m - 1) * 1e-6 * (i % 2 ? 1 : -1));    // also next to 1
  }
  check(0.0, -0.0);
  check(-1.0, std::numeric_limits<double>::infinity());
  check(std::nan(""), 5e-324);
  check(std::numeric_limits<double>::max(), std::numeric_limits<double>::min());
  check(1.0, 2.0);
  std::printf("[ log ] worst error against the C library's log: %.2f ulp\n", worst);
}

}  // namespace
}  // namespace qmaps
