// The case II kernels (kernels/case2.hpp, kernels/case2_hky.hpp), tested directly at V = double
// and V = long double: parameter validation; conservation of every invariant; the corrected
// q-forms of docs/maps.md §4, §5, §6 hold on computed orbits and the printed ones do not; the
// identities between the invariants and their continuum limits; case2-staggered as a relabelling
// of case2; the HKY map's parameters and its reduction to the symmetric map; reversibility.
// Tolerance bounds are about ten times the figures measured (printed by the tests).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/map_concept.hpp"
#include "core/params.hpp"
#include "kernels/case2.hpp"
#include "kernels/case2_hky.hpp"

namespace qmaps {
namespace {

using kernels::Case2;
using kernels::Case2Hky;
using kernels::Case2Staggered;

static_assert(KernelMap<Case2>);
static_assert(KernelMap<Case2Staggered>);
static_assert(KernelMap<Case2Hky>);

using LD = long double;
const std::array<Phase, 3> starts = {
    {{0.3, -0.2, 0.1, 0.4}, {0.5, 0.1, -0.3, 0.2}, {-0.1, 0.45, 0.25, -0.15}}};
constexpr double A = 0.7, alpha = 0.9;

ParamValues symmetric(double h) { return {{"A", A}, {"alpha", alpha}, {"h", h}}; }
ParamValues arbitrary_c(double h) {  // integrable, though not consistent with case II
  ParamValues p = symmetric(h);
  p.insert({{"c11", 0.37}, {"c12", 0.41}, {"c21", 0.77}, {"c22", 0.19}});
  return p;
}
ParamValues gammas(double h) {
  return {{"A", A}, {"alpha", alpha}, {"h", h}, {"gamma11", 0.6}, {"gamma21", 0.3}};
}

template <class M>
typename M::Coeffs coeffs(const ParamValues& p) {
  return M::coefficients(resolve_params(M::name, M::params, p));
}

template <class T>
std::array<T, 4> cast(const std::array<double, 4>& s) {
  return {T(s[0]), T(s[1]), T(s[2]), T(s[3])};
}

template <class M, class T>
std::array<T, 4> start(const typename M::Coeffs& c, const Phase& x) {
  return cast<T>(M::from_phase_space(c, x, Start::taylor));
}

// The states n = 0 … steps of the orbit from x.
template <class M, class T>
std::vector<std::array<T, 4>> orbit(const typename M::Coeffs& c, const Phase& x, int steps) {
  std::vector<std::array<T, 4>> out{start<M, T>(c, x)};
  for (int n = 0; n < steps; ++n) {
    out.push_back(out.back());
    M::step(c, out.back());
  }
  return out;
}

// max over n of |I_n − I_0| / |I_0|, per invariant, on the given states.
template <class M, class T>
std::array<double, 4> drift_of(const typename M::Coeffs& c,
                               const std::vector<std::array<T, 4>>& states) {
  std::array<T, 4> first{}, now{};
  M::invariants(c, states[0], first.data());
  std::array<double, 4> worst{};
  for (const auto& s : states) {
    M::invariants(c, s, now.data());
    for (int k = 0; k < 4; ++k)
      worst[k] = std::max(worst[k], static_cast<double>(std::fabs((now[k] - first[k]) / first[k])));
  }
  return worst;
}

// max over the three starts, 1000 steps.
template <class M, class T>
std::array<double, 4> drift(const typename M::Coeffs& c) {
  std::array<double, 4> worst{};
  for (const auto& x : starts) {
    const auto d = drift_of<M, T>(c, orbit<M, T>(c, x, 1000));
    for (int k = 0; k < 4; ++k) worst[k] = std::max(worst[k], d[k]);
  }
  return worst;
}

template <class M>
void expect_usage_error(const ParamValues& p, const std::string& fragment) {
  try {
    coeffs<M>(p);
    ADD_FAILURE() << M::name << " accepted: " << fragment;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::usage);
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Case2, RejectsInvalidParametersNamingTheProblem) {
  const double inf = std::numeric_limits<double>::infinity();
  expect_usage_error<Case2>({{"A", A}, {"alpha", alpha}}, "'h' is missing");
  expect_usage_error<Case2>({{"A", A}, {"alpha", inf}, {"h", 0.1}}, "'alpha' must be finite");
  expect_usage_error<Case2>({{"A", A}, {"alpha", alpha}, {"h", 0.0}}, "case2: h must be > 0");
  expect_usage_error<Case2>({{"A", A}, {"alpha", alpha}, {"h", -0.1}}, "h must be > 0 (got -0.1)");
  expect_usage_error<Case2>({{"A", 4.0}, {"alpha", alpha}, {"h", 0.5}}, "case2: 1 - A h^2 = 0");
  expect_usage_error<Case2>({{"A", A}, {"B", A}, {"alpha", alpha}, {"h", 0.1}}, "no parameter 'B'");
  expect_usage_error<Case2Staggered>({{"A", A}, {"alpha", alpha}, {"h", 0.0}},
                                     "case2-staggered: h must be > 0");
  expect_usage_error<Case2Staggered>({{"A", 1.0}, {"alpha", alpha}, {"h", 1.0}},
                                     "case2-staggered: 1 - A h^2 = 0");
}

TEST(Case2Hky, RejectsAnythingButExactlyOneCompleteCoefficientSet) {
  const std::string choice = "give either all of c11, c12, c21, c22 or both gamma11 and gamma21";
  for (const auto& spec : Case2Hky::params)
    if (spec.name[0] == 'c' || spec.name[0] == 'g') {
      EXPECT_TRUE(spec.optional) << spec.name;
      EXPECT_TRUE(std::isnan(spec.default_value)) << spec.name;
    }
  ParamValues p = symmetric(0.1);
  expect_usage_error<Case2Hky>(p, choice + " (got 0 of the c's, 0 of the gammas)");
  p = arbitrary_c(0.1);
  p.erase("c21");
  expect_usage_error<Case2Hky>(p, choice + " (got 3 of the c's, 0 of the gammas)");
  p = gammas(0.1);
  p.erase("gamma11");
  expect_usage_error<Case2Hky>(p, choice + " (got 0 of the c's, 1 of the gammas)");
  p = arbitrary_c(0.1);
  p["gamma21"] = 0.3;
  expect_usage_error<Case2Hky>(p, choice + ", not both sets");
  p = gammas(0.1);
  p["c11"] = 1;
  expect_usage_error<Case2Hky>(p, "not both sets");
  p = arbitrary_c(0.0);
  expect_usage_error<Case2Hky>(p, "case2-hky: h must be > 0 (got 0)");
  p = {{"A", 1.0}, {"alpha", alpha}, {"h", 1.0}, {"c11", 1}, {"c12", 0}, {"c21", 0}, {"c22", 0.5}};
  expect_usage_error<Case2Hky>(p, "case2-hky: 1 - A h^2 c11 = 0");
  p["c11"] = 0.5;  // k1 = 1: any c11 with A h² c11 ≠ 1 is accepted
  EXPECT_EQ(coeffs<Case2Hky>(p).k1, 1.0);
  EXPECT_EQ(Case2Hky::invariant_names(coeffs<Case2Hky>(gammas(0.1))),
            (std::vector<std::string>{"K+", "K-", "I1", "I2"}));
  EXPECT_EQ(Case2::invariant_names(coeffs<Case2>(symmetric(0.1))),
            (std::vector<std::string>{"H1", "H2", "I1", "I2"}));
}

// Every invariant of every map over 1000 steps from the three starts, h = 0.1 and 0.5. At
// long double only the rounding of the arithmetic remains (the coefficients are the same
// doubles), so an invariant inconsistent with the map's rounded coefficients shows up there:
// measured ≤ 1.4e-16, while c2 = 2Ah² instead of 2 − 2a (or HKY's n0, m1 from the c's instead of
// the k's) gives 2e-15 to 2e-14. Measured at double: ≤ 1.7e-13.
TEST(Case2, EveryInvariantIsConservedWithinTolerance) {
  struct Bound {
    double long_double, dbl;
  };
  const auto check = [](const char* what, double h, std::array<double, 4> ld,
                        std::array<double, 4> d, Bound b) {
    std::printf(
        "[ drift ] %-10s h=%.1f  long double %.1e %.1e %.1e %.1e  double %.1e %.1e %.1e %.1e\n",
        what, h, ld[0], ld[1], ld[2], ld[3], d[0], d[1], d[2], d[3]);
    for (int k = 0; k < 4; ++k) {
      EXPECT_LT(ld[k], b.long_double) << what << " h=" << h << " invariant " << k;
      EXPECT_LT(d[k], b.dbl) << what << " h=" << h << " invariant " << k;
      EXPECT_GT(d[k], 0.0) << what << ": a drift of exactly zero means nothing was measured";
    }
  };
  for (double h : {0.1, 0.5}) {
    const auto s = coeffs<Case2>(symmetric(h));
    check("case2", h, drift<Case2, LD>(s), drift<Case2, double>(s), {1e-15, 2e-12});
    const auto c = coeffs<Case2Hky>(arbitrary_c(h));
    check("hky c", h, drift<Case2Hky, LD>(c), drift<Case2Hky, double>(c), {1e-15, 2e-12});
    const auto g = coeffs<Case2Hky>(gammas(h));
    check("hky gamma", h, drift<Case2Hky, LD>(g), drift<Case2Hky, double>(g), {1e-15, 2e-12});
  }
}

// Residual of (discrete-case2) at node n, both equations, with the quartic coefficients
// k4·α(q1² + q2²)(S1/2) and k8·α q1q2 (S2/2), S_i = q_{i,n+1} + q_{i,n−1}: corrected (E6)
// k4 = 4, k8 = 8; printed k4 = 1, k8 = 2. The map's coefficients are doubles: their rounding,
// divided by h², sets the floor of the long double residual (about eps·|q|/h²).
template <class T>
T qform_residual(T h, T x1, T x2, T y1, T y2, T z1, T z2, T k4, T k8) {
  const T S1 = z1 + x1, S2 = z2 + x2, r2 = y1 * y1 + y2 * y2;
  const T e1 = (z1 - 2 * y1 + x1) / (h * h) + 2 * T(A) * y1 + k4 * T(alpha) * r2 * S1 / 2 +
               k8 * T(alpha) * y1 * y2 * S2 / 2;
  const T e2 = (z2 - 2 * y2 + x2) / (h * h) + 2 * T(A) * y2 + k4 * T(alpha) * r2 * S2 / 2 +
               k8 * T(alpha) * y1 * y2 * S1 / 2;
  return std::max(std::fabs(e1), std::fabs(e2));
}

TEST(Case2, CorrectedQFormHoldsOnTheOrbitAndPrintedFormDoesNotWithinTolerance) {
  for (double h : {0.1, 0.5}) {
    const auto c = coeffs<Case2>(symmetric(h));
    LD corrected_ld = 0;
    double corrected = 0, printed = 1e300;
    for (const auto& x : starts) {
      const auto ld = orbit<Case2, LD>(c, x, 1000);
      const auto d = orbit<Case2, double>(c, x, 1000);
      LD worst_printed = 0;
      for (std::size_t n = 1; n < ld.size(); ++n) {
        const auto &p = ld[n - 1], &q = ld[n];
        corrected_ld =
            std::max(corrected_ld, qform_residual<LD>(h, p[0], p[1], q[0], q[1], q[2], q[3], 4, 8));
        worst_printed = std::max(worst_printed,
                                 qform_residual<LD>(h, p[0], p[1], q[0], q[1], q[2], q[3], 1, 2));
        const auto &pd = d[n - 1], &qd = d[n];
        corrected = std::max(
            corrected, qform_residual<double>(h, pd[0], pd[1], qd[0], qd[1], qd[2], qd[3], 4, 8));
      }
      printed = std::min(printed, static_cast<double>(worst_printed));
    }
    std::printf("[ q-form ] h=%.1f  corrected: long double %.1Le, double %.1e;  printed %.2e\n", h,
                corrected_ld, corrected, printed);
    EXPECT_LT(corrected_ld, 1e-14L);
    EXPECT_LT(corrected, 3e-13);
    EXPECT_GT(printed, 1e-2);
  }
}

// Residuals of (discrete-case2-2) as printed, in the paper's indexing (q2_m = Q2_{m+1}), on a
// case2-staggered orbit: with the E6 factor they vanish, as printed they do not.
TEST(Case2Staggered, PaperIndexedAsymmetricEquationsHoldOnItsOrbitWithinTolerance) {
  const double h = 0.1;
  const auto c = coeffs<Case2Staggered>(symmetric(h));
  for (const auto& x : starts) {
    const auto states = orbit<Case2Staggered, LD>(c, x, 1000);
    std::vector<LD> q1, q2p;  // q1_n, the paper's q2_m = Q2_{m+1}
    for (const auto& s : states) {
      q1.push_back(s[0]);
      q2p.push_back(s[3]);  // state n holds (q1_n, q2_{n-1}, q1_{n+1}, q2_n)
    }
    // q2p[m] is the paper's q2_m for m ≥ 0; the paper's q2_{−1} = states[0][1].
    const auto Q = [&](long m) { return m < 0 ? states[0][1] : q2p[m]; };
    LD corrected = 0, printed = 0;
    for (long n = 1; n + 2 < static_cast<long>(q1.size()); ++n) {
      for (LD k : {LD(4), LD(1)}) {
        const LD e1 =
            (q1[n + 1] - 2 * q1[n] + q1[n - 1]) / (h * h) + 2 * A * q1[n] +
            k * alpha * (q1[n] * q1[n] + Q(n - 1) * Q(n - 1)) * (q1[n + 1] + q1[n - 1]) / 2 +
            2 * k * alpha * q1[n] * Q(n - 1) * (Q(n) + Q(n - 2)) / 2;
        const LD e2 =
            (Q(n + 1) - 2 * Q(n) + Q(n - 1)) / (h * h) + 2 * A * Q(n) +
            k * alpha * (q1[n + 1] * q1[n + 1] + Q(n) * Q(n)) * (Q(n + 1) + Q(n - 1)) / 2 +
            2 * k * alpha * Q(n) * q1[n + 1] * (q1[n + 2] + q1[n]) / 2;
        LD& worst = k == 4 ? corrected : printed;
        worst = std::max({worst, std::fabs(e1), std::fabs(e2)});
      }
    }
    std::printf("[ q-form ] staggered: corrected %.1Le, printed %.2Le\n", corrected, printed);
    EXPECT_LT(corrected, 1e-14L);
    EXPECT_GT(printed, 1e-2L);
  }
}

TEST(Case2, InvariantsAreHalfSumAndHalfDifferenceOfH1H2WithinTolerance) {
  for (double h : {0.1, 0.5}) {
    const auto c = coeffs<Case2>(symmetric(h));
    double worst = 0;
    for (const auto& x : starts)
      for (const auto& s : orbit<Case2, double>(c, x, 200)) {
        std::array<double, 4> v;  // H1, H2, I1, I2
        Case2::invariants(c, s, v.data());
        const double scale = std::fabs(v[0]) + std::fabs(v[1]);
        worst = std::max({worst, std::fabs(v[2] - (v[0] + v[1]) / 2) / scale,
                          std::fabs(v[3] - (v[0] - v[1]) / 2) / scale});
      }
    std::printf("[ identity ] h=%.1f  |I1 - (H1+H2)/2|, |I2 - (H1-H2)/2| <= %.1e (|H1|+|H2|)\n", h,
                worst);
    EXPECT_LT(worst, 2e-15);
  }
}

// I1 → H and I2 → p1p2 + 2q1q2[A + 2α|q|²] at the starting state, with an error of order 2 in h.
template <class M>
void expect_second_order_limits(ParamValues (*params)(double)) {
  for (const auto& x : starts) {
    const double r2 = x.q1 * x.q1 + x.q2 * x.q2;
    const double H = (x.p1 * x.p1 + x.p2 * x.p2) / 2 + A * r2 +
                     alpha * (x.q1 * x.q1 * x.q1 * x.q1 + x.q2 * x.q2 * x.q2 * x.q2) +
                     6 * alpha * x.q1 * x.q1 * x.q2 * x.q2;
    const double I = x.p1 * x.p2 + 2 * x.q1 * x.q2 * (A + 2 * alpha * r2);
    std::array<double, 2> previous{};
    for (double h : {0.04, 0.02, 0.01, 0.005}) {
      const auto c = coeffs<M>(params(h));
      std::array<double, 4> v;
      M::invariants(c, M::from_phase_space(c, x, Start::taylor), v.data());
      const std::array<double, 2> err = {std::fabs(v[2] - H), std::fabs(v[3] - I)};
      std::printf("[ limit ] %s h=%.3f  |I1 - H| %.2e  |I2 - I| %.2e\n",
                  std::string(M::name).c_str(), h, err[0], err[1]);
      for (int k = 0; k < 2; ++k) {
        EXPECT_LT(err[k], 0.5 * h * h) << k;
        if (previous[k] > 0) {
          EXPECT_GT(previous[k] / err[k], 3.5) << "h = " << h << " invariant " << k;
          EXPECT_LT(previous[k] / err[k], 5.0) << "h = " << h << " invariant " << k;
        }
      }
      previous = err;
    }
  }
}

TEST(Case2, InvariantsTendToHAndTheSecondIntegralAtSecondOrderWithinTolerance) {
  expect_second_order_limits<Case2>(symmetric);
  expect_second_order_limits<Case2Hky>(gammas);
}

TEST(Case2Staggered, SameStateArrayGivesIdenticalStepsAndInvariants) {
  const auto c = coeffs<Case2>(symmetric(0.1));
  const auto cs = coeffs<Case2Staggered>(symmetric(0.1));
  EXPECT_EQ(0, std::memcmp(&c, &cs, sizeof c));
  for (const auto& x : starts) {
    auto a = Case2::from_phase_space(c, x, Start::taylor);
    auto b = Case2Staggered::from_phase_space(cs, x, Start::taylor);
    for (int n = 0; n <= 1000; ++n) {
      ASSERT_EQ(0, std::memcmp(a.data(), b.data(), sizeof a)) << "step " << n;
      std::array<double, 4> ia, ib;
      Case2::invariants(c, a, ia.data());
      Case2Staggered::invariants(cs, b, ib.data());
      ASSERT_EQ(0, std::memcmp(ia.data(), ib.data(), sizeof ia)) << "step " << n;
      Case2::step(c, a);
      Case2Staggered::step(cs, b);
    }
    const Phase pa = Case2::to_phase_space(c, a), pb = Case2Staggered::to_phase_space(cs, b);
    EXPECT_EQ(0, std::memcmp(&pa, &pb, sizeof pa));
  }
  EXPECT_NE(Case2::name, Case2Staggered::name);
  EXPECT_EQ(Case2Staggered::state_names[1], "q2_n-1");
}

// The paper's printed I1, I2 read with the naive pairing (q1_n, q2_n; q1_{n+1}, q2_{n+1}) of a
// case2-staggered orbit are not invariant; with the staggered pairing (the state) they are.
TEST(Case2Staggered, NaivePairingIsNotConservedWithinTolerance) {
  const auto c = coeffs<Case2Staggered>(symmetric(0.1));
  std::array<double, 4> naive{}, staggered{};
  for (const auto& x : starts) {
    const auto states = orbit<Case2Staggered, LD>(c, x, 1001);
    std::vector<std::array<LD, 4>> paired;  // (q1_n, q2_n, q1_n+1, q2_n+1), paper's indices
    for (std::size_t n = 0; n + 1 < states.size(); ++n)
      paired.push_back({states[n][0], states[n][3], states[n][2], states[n + 1][3]});
    const auto dn = drift_of<Case2Staggered, LD>(c, paired);
    const auto ds = drift_of<Case2Staggered, LD>(c, states);
    for (int k = 0; k < 4; ++k) {
      naive[k] = std::max(naive[k], dn[k]);
      staggered[k] = std::max(staggered[k], ds[k]);
    }
  }
  std::printf("[ pairing ] naive drift H1 %.1e H2 %.1e I1 %.1e I2 %.1e;  staggered max %.1e\n",
              naive[0], naive[1], naive[2], naive[3],
              *std::max_element(staggered.begin(), staggered.end()));
  for (int k = 0; k < 4; ++k) {
    EXPECT_GT(naive[k], 1e-4) << k;
    EXPECT_LT(staggered[k], 1e-15) << k;
  }
}

TEST(Case2Hky, GammaParametrisationGivesTheStatedCoefficientsWithinTolerance) {
  for (double h : {0.1, 0.5}) {
    const auto c = coeffs<Case2Hky>(gammas(h));
    const LD Ah2 = LD(A) * h * h, g11 = 0.6L, g12 = (1 - g11) / 2, g21 = 0.3L, g22 = 1 - g21;
    const std::array<LD, 4> expected = {g11, g12, (1 - Ah2 * g11) * g21,
                                        (1 + 2 * Ah2 * g12) * g22 / 2};
    const std::array<double, 4> got = {c.c11, c.c12, c.c21, c.c22};
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(got[k], expected[k], 1e-16L) << k;
    // consistency with case II: c11 + 2 c12 = 1, c21 + 2 c22 = 1 + Ah²(2γ12γ22 − γ11γ21)
    EXPECT_NEAR(c.c11 + 2 * c.c12, 1.0, 1e-15);
    EXPECT_NEAR(c.c21 + 2 * c.c22, 1 + Ah2 * (2 * g12 * g22 - g11 * g21), 1e-15L);
    EXPECT_NEAR(c.k0, 1 + 2 * Ah2 * g12, 1e-15L);
    EXPECT_NEAR(c.k1, 2 * (1 - Ah2 * g11), 1e-15L);
  }
}

TEST(Case2Hky, GammaSetAndItsCoefficientsGiveIdenticalOrbits) {
  const auto g = coeffs<Case2Hky>(gammas(0.1));
  ParamValues p = symmetric(0.1);
  p.insert({{"c11", g.c11}, {"c12", g.c12}, {"c21", g.c21}, {"c22", g.c22}});
  const auto c = coeffs<Case2Hky>(p);
  for (const auto& x : starts) {
    const auto a = orbit<Case2Hky, double>(g, x, 1000), b = orbit<Case2Hky, double>(c, x, 1000);
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]));
  }
}

// c = (1, 0, 0, ½): k0 = 1, k1 = 2a, k2 = g, k3 = 0, the very coefficients of case2.
ParamValues symmetric_c(double h) {
  ParamValues p = symmetric(h);
  p.insert({{"c11", 1}, {"c12", 0}, {"c21", 0}, {"c22", 0.5}});
  return p;
}

TEST(Case2Hky, SymmetricCoefficientsGiveCase2CoefficientsEqual) {
  for (double h : {0.1, 0.5, 0.7}) {
    const auto s = coeffs<Case2>(symmetric(h));
    const auto c = coeffs<Case2Hky>(symmetric_c(h));
    EXPECT_EQ(c.k0, 1.0);
    EXPECT_EQ(c.k1, s.two_a);
    EXPECT_EQ(c.k2, s.g);
    EXPECT_EQ(c.k3, 0.0);
  }
}

// The update differs only in rounding: (k1 y − x f)/f against 2a y·(1/f) − x.
TEST(Case2Hky, SymmetricCoefficientsGiveTheCase2MapWithinTolerance) {
  for (double h : {0.1, 0.5}) {
    const auto s = coeffs<Case2>(symmetric(h));
    const auto c = coeffs<Case2Hky>(symmetric_c(h));
    double worst_state = 0, worst_energy = 0;
    const double a = s.two_a / 2;
    for (const auto& x : starts) {
      const auto p = orbit<Case2, double>(s, x, 1000), q = orbit<Case2Hky, double>(c, x, 1000);
      for (std::size_t n = 0; n < p.size(); ++n) {
        for (int k = 0; k < 4; ++k)
          worst_state = std::max(worst_state, std::fabs(p[n][k] - q[n][k]));
        std::array<double, 4> H, K;  // H1, H2, I1, I2 and K+, K-, I1, I2
        Case2::invariants(s, p[n], H.data());
        Case2Hky::invariants(c, p[n], K.data());
        for (int k = 0; k < 2; ++k)  // E± = K±/h² = H±/a
          worst_energy =
              std::max(worst_energy, std::fabs(K[k] / (h * h) - H[k] / a) / std::fabs(H[k]));
        for (int k = 2; k < 4; ++k)
          worst_energy = std::max(worst_energy, std::fabs(K[k] - H[k] / a) / std::fabs(H[2]));
      }
    }
    std::printf("[ hky = case2 ] h=%.1f  |q_hky - q_case2| <= %.1e, |E - H/a| <= %.1e relative\n",
                h, worst_state, worst_energy);
    EXPECT_LT(worst_state, 3e-12);
    EXPECT_LT(worst_energy, 1e-14);
  }
}

// Residuals of (discrete-case3) on an HKY orbit with arbitrary c's: the corrected q-form of
// docs/maps.md §6 vanishes, the printed one, erratum E9 (docs/maps.md §9), does not. The floor is
// set by the rounding of the map's double coefficients k0 … k3, divided by h².
TEST(Case2Hky, CorrectedQFormHoldsOnTheOrbitAndPrintedFormDoesNotWithinTolerance) {
  const double h = 0.1;
  const auto c = coeffs<Case2Hky>(arbitrary_c(h));
  const LD c11 = c.c11, c12 = c.c12, c21 = c.c21, c22 = c.c22, al = alpha;
  LD corrected = 0, printed = 0;
  for (const auto& x : starts) {
    const auto states = orbit<Case2Hky, LD>(c, x, 1000);
    for (std::size_t n = 1; n < states.size(); ++n) {
      // (m, y, p) = (q_{n−1}, q_n, q_{n+1}); the q2 equation is the q1 one with 1 ↔ 2
      const std::array<LD, 2> m = {states[n - 1][0], states[n - 1][1]},
                              y = {states[n][0], states[n][1]}, p = {states[n][2], states[n][3]};
      for (int i = 0; i < 2; ++i) {
        const int j = 1 - i;
        const LD lhs =
            (p[i] - 2 * y[i] + m[i]) / (h * h) + 2 * A * (c11 * y[i] + c12 * (p[i] + m[i]));
        const LD fixed =
            lhs + 4 * al * c22 * (y[i] * y[i] + y[j] * y[j]) * (p[i] + m[i]) +
            8 * al * c22 * y[i] * y[j] * (p[j] + m[j]) +
            4 * al * c21 *
                (y[i] * (p[i] * m[i] + p[j] * m[j]) + y[j] * (p[i] * m[j] + m[i] * p[j]));
        const LD as_printed =
            lhs + 4 * al * c22 * (y[i] * y[i] + 2 * al * y[j] * y[j]) * (p[i] + m[i]) +
            8 * al * c22 * y[i] * (y[j] * (p[j] + m[j])) +
            2 * al * c21 * (y[j] * p[j] * (p[i] + m[i]) + y[0] * p[0] * m[0] + y[1] * p[1] * m[1]);
        corrected = std::max(corrected, std::fabs(fixed));
        printed = std::max(printed, std::fabs(as_printed));
      }
    }
  }
  std::printf("[ q-form ] hky: corrected %.1Le, printed %.2Le\n", corrected, printed);
  EXPECT_LT(corrected, 1e-13L);
  EXPECT_GT(printed, 1e-2L);
}

TEST(Case2, StartAndPhaseSpaceConversionsWithinTolerance) {
  const auto c = coeffs<Case2>(symmetric(0.1));
  const Phase x{0.3, -0.2, 0.1, 0.4};
  const auto euler = Case2::from_phase_space(c, x, Start::euler);
  EXPECT_EQ(euler[2], 0.3 + 0.1 * 0.1);
  EXPECT_EQ(euler[3], -0.2 + 0.1 * 0.4);
  const auto taylor = Case2::from_phase_space(c, x, Start::taylor);
  EXPECT_EQ(taylor[2],
            euler[2] + 0.5 * 0.1 * 0.1 * (-2 * A * 0.3 - 4 * alpha * 0.3 * (0.09 + 3 * 0.04)));
  const auto hky = coeffs<Case2Hky>(gammas(0.1));
  EXPECT_EQ(0, std::memcmp(taylor.data(), Case2Hky::from_phase_space(hky, x, Start::taylor).data(),
                           sizeof taylor));
  EXPECT_EQ(Case2::time(c, 250, taylor), 250 * 0.1);
  EXPECT_EQ(Case2Hky::time(hky, 250, taylor), 250 * 0.1);
  double previous = 0;
  for (double h : {0.1, 0.05, 0.025}) {  // central difference: p to second order
    const auto ch = coeffs<Case2>(symmetric(h));
    const Phase back = Case2::to_phase_space(ch, Case2::from_phase_space(ch, x, Start::taylor));
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

template <class M>
double reversal_error(const typename M::Coeffs& c) {
  double worst = 0;
  for (const auto& x : starts) {
    const auto s0 = M::from_phase_space(c, x, Start::taylor);
    auto s = s0;
    for (int n = 0; n < 1000; ++n) M::step(c, s);
    s = M::reversed(c, s);
    for (int n = 0; n < 1000; ++n) M::step(c, s);
    const auto back = M::reversed(c, s);
    for (int k = 0; k < 4; ++k) worst = std::max(worst, std::fabs(back[k] - s0[k]));
  }
  return worst;
}

TEST(Case2, ReversedRunReturnsToStartWithinTolerance) {
  for (double h : {0.1, 0.5}) {
    const std::array<double, 4> e = {
        reversal_error<Case2>(coeffs<Case2>(symmetric(h))),
        reversal_error<Case2Staggered>(coeffs<Case2Staggered>(symmetric(h))),
        reversal_error<Case2Hky>(coeffs<Case2Hky>(arbitrary_c(h))),
        reversal_error<Case2Hky>(coeffs<Case2Hky>(gammas(h)))};
    std::printf("[ reversal ] h=%.1f  case2 %.1e, staggered %.1e, hky c %.1e, hky gamma %.1e\n", h,
                e[0], e[1], e[2], e[3]);
    for (int k = 0; k < 4; ++k) EXPECT_LT(e[k], 1e-12) << "h = " << h << " map " << k;
  }
}

}  // namespace
}  // namespace qmaps
