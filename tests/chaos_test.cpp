// The chaos indicators of core/chaos.hpp (tangent map, λ_max, FLI, MEGNO) on every map:
// - on the bounded orbits of the integrable maps, over 10⁵ steps, ⟨Y⟩ → 2 and λ_n decays like
//   ln(n)/n;
// - on the flow at non-integrable parameters (β = α, δ = 12α: a homogeneous quartic with a
//   chaotic sea), λ_n stays positive and ⟨Y⟩ grows linearly, as λ n / 2;
// - a batch's lanes give the scalar path's bits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/chaos.hpp"
#include "kernels/catalogue.hpp"
#include "kernels/maps.hpp"

namespace qmaps {
namespace {

struct Indicators {
  double lyapunov, fli, megno;
};

Indicators after(const Model& model, const Phase& x, long long steps) {
  Ensemble e = model.start(std::span(&x, 1), Start::taylor, 1e8);
  std::vector<double> state(model.state_names().size()), deviation(state.size());
  for (std::size_t k = 0; k < state.size(); ++k) {
    state[k] = e.state[k][0];
    deviation[k] = k < 4 ? 0.5 : 0.0;
  }
  ChaosSums<double> sums;
  EXPECT_EQ(model.advance_with_tangent(state, deviation, sums, steps), 0.0) << model.name();
  return {sums.lyapunov(), sums.fli, sums.megno()};
}

// Margins of the integrable maps' indicators at 10⁵ steps. ⟨Y⟩ approaches 2 as 2 − O(ln n/n)
// (measured 1.983 for Suris); λ_n ≤ ln(n)/n (measured 0.65 ln(n)/n).
constexpr double megno_margin = 0.1;

TEST(Chaos, IntegrableMapsHaveMegnoTwoAndLyapunovDecayingAsLogNOverN) {
  for (const MapEntry& m : catalogue()) {
    const auto model = make_model(m.name, param_values(m.facts->example));
    for (const Phase& x : {Phase{0.3, 0.2, 0.1, 0.25}, Phase{-0.4, 0.1, 0.3, -0.2}}) {
      for (long long n : {10000LL, 100000LL}) {
        const Indicators i = after(*model, x, n);
        const double bound = std::log(static_cast<double>(n)) / static_cast<double>(n);
        EXPECT_LE(std::fabs(i.lyapunov), bound) << m.name << " n = " << n;
        if (n == 100000) {
          EXPECT_NEAR(i.megno, 2.0, megno_margin) << m.name;
          std::printf("[ chaos ] %-16s n = 1e5: lambda = %.2e (ln(n)/n = %.2e), FLI = %.2f, <Y> = %.4f\n",
                      std::string(m.name).c_str(), i.lyapunov, bound, i.fli, i.megno);
        }
      }
    }
  }
}

TEST(Chaos, NonIntegrableFlowHasPositiveLyapunovAndMegnoGrowingLinearly) {
  const auto model = make_model("flow", {{"A", 0.0}, {"B", 0.0}, {"alpha", 0.25}, {"beta", 0.25},
                                         {"delta", 3.0}, {"h", 0.05}});
  for (const Phase& x : {Phase{0.5, 0.5, 0.3, 0.6}, Phase{1.0, 0.2, 0.0, 0.9}}) {
    const Indicators half = after(*model, x, 10000), whole = after(*model, x, 20000);
    std::printf("[ chaos ] flow, delta = 12 alpha: lambda = %.4f per step, <Y> %.1f -> %.1f "
                "(lambda n / 2 = %.1f)\n", whole.lyapunov, half.megno, whole.megno,
                whole.lyapunov * 20000 / 2);
    EXPECT_GT(whole.lyapunov, 0.005);
    EXPECT_GT(whole.fli, 100.0);
    EXPECT_NEAR(whole.megno / half.megno, 2.0, 0.4);                   // linear growth
    EXPECT_NEAR(whole.megno, whole.lyapunov * 20000 / 2, 0.2 * whole.megno);  // ≈ λ n / 2
  }
}

// Two orbits in the lanes of an SSE2 batch (the ISA of every x86-64 build) give, step by step,
// the scalar path's bits: state, deviation and sums.
TEST(Chaos, BatchLanesGiveTheScalarBits) {
  using B = xsimd::batch<double, xsimd::sse2>;
  kernels::for_each_map([](auto map) {
    using Map = decltype(map);
    const auto values = resolve_params(Map::name, Map::params, param_values(Map::facts.example));
    const auto c = Map::coefficients(values);
    const auto s0 = Map::from_phase_space(c, Phase{0.3, 0.2, 0.1, 0.25}, Start::taylor);
    const auto s1 = Map::from_phase_space(c, Phase{-0.4, 0.1, 0.3, -0.2}, Start::taylor);
    auto a = s0, b = s1;
    constexpr std::size_t S = std::tuple_size_v<decltype(a)>;
    auto wa = initial_deviation<double, S>(), wb = wa;
    ChaosSums<double> sa, sb;
    typename Map::template State<B> s, w = initial_deviation<B, S>();
    for (std::size_t k = 0; k < S; ++k) {
      alignas(16) const double two[2] = {s0[k], s1[k]};
      s[k] = B::load_aligned(two);
    }
    ChaosSums<B> sums;
    for (int n = 0; n < 200; ++n) {
      chaos_step<Map>(c, a, wa, sa);
      chaos_step<Map>(c, b, wb, sb);
      chaos_step<Map>(c, s, w, sums);
    }
    const auto same = [](B batch, double lane0, double lane1) {
      const auto l = ops::lanes_of(batch);
      return std::bit_cast<std::uint64_t>(l[0]) == std::bit_cast<std::uint64_t>(lane0) &&
             std::bit_cast<std::uint64_t>(l[1]) == std::bit_cast<std::uint64_t>(lane1);
    };
    for (std::size_t k = 0; k < S; ++k) {
      EXPECT_TRUE(same(s[k], a[k], b[k])) << Map::name;
      EXPECT_TRUE(same(w[k], wa[k], wb[k])) << Map::name;
    }
    EXPECT_TRUE(same(sums.log_growth, sa.log_growth, sb.log_growth)) << Map::name;
    EXPECT_TRUE(same(sums.fli, sa.fli, sb.fli)) << Map::name;
    EXPECT_TRUE(same(sums.megno_sum, sa.megno_sum, sb.megno_sum)) << Map::name;
  });
}

}  // namespace
}  // namespace qmaps
