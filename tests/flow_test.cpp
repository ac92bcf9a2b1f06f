// The continuous-flow kernels (Flow, Leapfrog): validation, the order of each composition, the
// conservation of H and of each case's second integral, case detection, reversibility, and the
// second integrals themselves ({I, H} = 0). The kernels are called directly, at V = double and
// V = long double; one test compares a batch with the scalar path bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.hpp"
#include "core/isa.hpp"
#include "core/map_concept.hpp"
#include "ensemble_fixtures.hpp"
#include "isas_run.hpp"
#include "kernels/flow.hpp"

namespace qmaps {
namespace {

using kernels::Flow;
using kernels::Leapfrog;

static_assert(KernelMap<Flow>);
static_assert(KernelMap<Leapfrog>);
static_assert(Flow::params.size() == 7 && Leapfrog::params.size() == 6);

// (A, B, alpha, beta, delta) of each case, from the example A = 0.7, α = 0.9 (docs/maps.md §2),
// and a set that satisfies none.
using Potential = std::array<double, 5>;
constexpr double A0 = 0.7, a0 = 0.9;
constexpr std::array<Potential, 4> cases = {{{A0, 0.3, a0, a0, 2 * a0},
                                             {A0, A0, a0, a0, 6 * a0},
                                             {A0, 4 * A0, a0, 16 * a0, 12 * a0},
                                             {A0, 4 * A0, a0, 8 * a0, 6 * a0}}};
constexpr std::array<std::string_view, 4> names = {"I", "II", "III", "IV"};
constexpr Potential generic = {A0, 0.3, a0, 0.5, 0.4};
// The initial conditions of docs/maps.md §2.
constexpr std::array<std::array<double, 4>, 3> starts = {
    {{0.3, -0.2, 0.1, 0.4}, {0.5, 0.1, -0.3, 0.2}, {-0.1, 0.45, 0.25, -0.15}}};

Flow::Coeffs flow(const Potential& v, double h, double order = 8) {
  return Flow::coefficients(std::array{v[0], v[1], v[2], v[3], v[4], h, order});
}
Leapfrog::Coeffs leapfrog(const Potential& v, double h) {
  return Leapfrog::coefficients(std::array{v[0], v[1], v[2], v[3], v[4], h});
}

template <class M, class V>
std::array<V, 4> run(const typename M::Coeffs& c, std::array<V, 4> s, long long n) {
  for (long long i = 0; i < n; ++i) M::step(c, s);
  return s;
}

// max over n ≤ steps of |I_n − I_0| / |I_0| for each reported invariant, at V.
template <class M, class V>
std::vector<double> drift(const typename M::Coeffs& c, const std::array<double, 4>& x,
                          long long steps) {
  std::array<V, 4> s = {V(x[0]), V(x[1]), V(x[2]), V(x[3])};
  const std::size_t k = M::invariant_names(c).size();
  V first[2], now[2];
  M::invariants(c, s, first);
  std::vector<double> d(k, 0.0);
  for (long long n = 0; n < steps; ++n) {
    M::step(c, s);
    M::invariants(c, s, now);
    for (std::size_t j = 0; j < k; ++j) {
      const auto r = std::fabs(now[j] - first[j]) / std::fabs(first[j]);
      d[j] = std::max(d[j], static_cast<double>(r));
    }
  }
  return d;
}

// The largest drift over the three starts.
template <class M, class V = double>
std::vector<double> worst_drift(const typename M::Coeffs& c, double t) {
  std::vector<double> worst;
  for (const auto& x : starts) {
    const auto d = drift<M, V>(c, x, std::llround(t / c.h));
    worst.resize(d.size(), 0.0);
    for (std::size_t j = 0; j < d.size(); ++j) worst[j] = std::max(worst[j], d[j]);
  }
  return worst;
}

void expect_usage_error(auto make, const std::string& fragment) {
  try {
    make();
    ADD_FAILURE() << "accepted: " << fragment;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ExitCode::usage);
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Flow, RejectsInvalidParametersNamingTheProblem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double h : {0.0, -0.1, nan}) {
    expect_usage_error([&] { flow(generic, h); }, "flow: h must be > 0");
    expect_usage_error([&] { leapfrog(generic, h); }, "leapfrog: h must be > 0");
  }
  for (double order : {0.0, 1.0, 3.0, 5.0, 7.5, 10.0, -8.0, nan})
    expect_usage_error([&] { flow(generic, 0.1, order); }, "flow: order must be 2, 4, 6 or 8");
  // Case I with (B − A)/α beyond the doubles.
  expect_usage_error([] { flow({0, 1, 1e-310, 1e-310, 2e-310}, 0.1); }, "overflows");
  for (double order : {2.0, 4.0, 6.0, 8.0}) EXPECT_EQ(flow(generic, 0.1, order).order, order);
}

TEST(Flow, ParametersAndDefaults) {
  const std::array<std::string_view, 7> expected = {"A",     "B", "alpha", "beta",
                                                    "delta", "h", "order"};
  for (std::size_t k = 0; k < 7; ++k) EXPECT_EQ(Flow::params[k].name, expected[k]);
  for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(Leapfrog::params[k].name, expected[k]);
  EXPECT_EQ(Flow::params[6].default_value, 6);  // docs/maps.md §8: best above h ≈ 1/140
  for (std::size_t k = 0; k < 6; ++k) EXPECT_TRUE(Flow::params[k].required()) << expected[k];
}

TEST(Flow, CompositionsAreSymmetricAndConsistent) {
  const std::array<int, 4> stages = {1, 3, 7, 15};
  for (int i = 0; i < 4; ++i) {
    const auto c = flow(generic, 0.125, 2 * (i + 1));
    const auto s = static_cast<std::size_t>(c.stages);
    ASSERT_EQ(c.stages, stages[static_cast<std::size_t>(i)]);  // s force evaluations per step
    double kicks = 0, drifts = 0;
    for (std::size_t j = 0; j <= s; ++j) {
      drifts += c.drift[j];
      EXPECT_EQ(c.drift[j], c.drift[s - j]);
    }
    for (std::size_t j = 0; j < s; ++j) {
      kicks += c.kick[j];
      EXPECT_EQ(c.kick[j], c.kick[s - 1 - j]);
    }
    EXPECT_NEAR(kicks, 0.125, 1e-15) << c.order;
    EXPECT_NEAR(drifts, 0.125, 1e-15) << c.order;
  }
}

TEST(Flow, LeapfrogIsTheOrderTwoFlowBitForBit) {
  const auto f = flow(cases[3], 0.05, 2);
  const auto l = leapfrog(cases[3], 0.05);
  for (const auto& x : starts) {
    const auto a = run<Flow>(f, x, 500), b = run<Leapfrog>(l, x, 500);
    EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof a), 0);
  }
  EXPECT_EQ(Leapfrog::invariant_names(l), Flow::invariant_names(f));
}

// Every composition on every ISA run here, through the runner, equals the scalar reference byte
// for byte: states and invariants.
TEST(Flow, EveryIsaEqualsScalarByteForByteAtEveryOrder) {
  const auto isas = testing::isas_to_run();
  ASSERT_FALSE(isas.empty());
  const auto points = testing::box_points(1001, 0.5, 0.5, 7);
  for (double order : {2.0, 4.0, 6.0, 8.0}) {
    const auto model = make_model("flow", {{"A", 0.7}, {"B", 2.8}, {"alpha", 0.9}, {"beta", 7.2},
                                           {"delta", 5.4}, {"h", 0.05}, {"order", order}});
    RunPlan plan;
    plan.total = plan.last = 200;
    Ensemble ref = model->start(points, Start::taylor, plan.escape_bound);
    model->advance(ref, plan, Execution{});
    for (Isa isa : isas) {
      Ensemble e = model->start(points, Start::taylor, plan.escape_bound);
      model->advance(e, plan, Execution{isa, 2, 4});
      for (std::size_t i = 0; i < e.orbits; ++i) {
        const auto a = model->invariants(ref, i), b = model->invariants(e, i);
        for (std::size_t k = 0; k < e.state.size(); ++k)
          ASSERT_EQ(std::memcmp(&ref.state[k][i], &e.state[k][i], sizeof(double)), 0)
              << isa_name(isa) << " order " << order << " orbit " << i << " state " << k << ": "
              << ref.state[k][i] << " vs " << e.state[k][i];
        ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0)
            << isa_name(isa) << " order " << order << " orbit " << i << " invariants";
      }
    }
  }
}

TEST(Flow, MeasuredOrderOfEachCompositionWithinTolerance) {
  // Error at t = 1 against order 8 at h = 1/1024, all in long double; order from h = 1/32, 1/64.
  const std::array<long double, 4> x = {0.5L, 0.1L, -0.3L, 0.2L};
  const auto ref = run<Flow>(flow(generic, 1.0 / 1024), x, 1024);
  const auto error = [&](double order, int n) {
    const auto s = run<Flow>(flow(generic, 1.0 / n, order), x, n);
    long double e = 0;
    for (std::size_t k = 0; k < 4; ++k) e = std::max(e, std::fabs(s[k] - ref[k]));
    return static_cast<double>(e);
  };
  for (double order : {2.0, 4.0, 6.0, 8.0}) {
    const double e32 = error(order, 32), e64 = error(order, 64);
    const double measured = std::log2(e32 / e64);
    std::printf("order %g: error %.3e (h = 1/32), %.3e (h = 1/64), measured order %.3f\n", order,
                e32, e64, measured);
    EXPECT_NEAR(measured, order, 0.3);
  }
}

TEST(Flow, InvariantsConservedToTheMethodsOrderWithinTolerance) {
  // Drift ∝ h^order: log2 of the drift ratio from h = 0.02 to 0.01 over t = T, in long double
  // (rounding stays below the order-8 drifts at h = 0.01).
  constexpr double T = 20;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    std::printf("case %-3s drift order (H, I):", std::string(names[i]).c_str());
    for (double order : {2.0, 4.0, 6.0, 8.0}) {
      const auto d1 = worst_drift<Flow, long double>(flow(cases[i], 0.02, order), T);
      const auto d2 = worst_drift<Flow, long double>(flow(cases[i], 0.01, order), T);
      ASSERT_EQ(d1.size(), 2u);
      const double H = std::log2(d1[0] / d2[0]), I = std::log2(d1[1] / d2[1]);
      std::printf("  %g: %.2f %.2f", order, H, I);
      EXPECT_NEAR(H, order, 0.3) << "case " << names[i] << " order " << order;
      EXPECT_NEAR(I, order, 0.3) << "case " << names[i] << " order " << order;
    }
    std::printf("\n");
  }
}

TEST(Flow, DriftsOfEveryCaseAtStepFiveHundredthsOverTimeHundred) {
  std::printf("relative drift max_n |I_n - I_0|/|I_0|, h = 0.05, t = 100, three starts:\n");
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto l = worst_drift<Leapfrog>(leapfrog(cases[i], 0.05), 100);
    std::printf("case %-3s leapfrog H %.2e I %.2e", std::string(names[i]).c_str(), l[0], l[1]);
    for (double order : {4.0, 6.0, 8.0}) {
      const auto d = worst_drift<Flow>(flow(cases[i], 0.05, order), 100);
      std::printf(" | order %g H %.2e I %.2e", order, d[0], d[1]);
      EXPECT_LT(d[0], 3e-3);
    }
    std::printf("\n");
    EXPECT_LT(l[0], 0.02);
  }
}

TEST(Flow, CaseFourOrderEightAtStepHundredthWithinTolerance) {
  // Yoshida's solution A has a large error constant: the third start (q2 = 0.45, β = 7.2) drifts
  // 1.0e-9 in H at h = 0.01; the first two 6e-11 and 7e-12. Each halving of h divides it by 256.
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const auto f = drift<Flow, double>(flow(cases[3], 0.01), starts[k], 10000);
    const auto f2 = drift<Flow, double>(flow(cases[3], 0.005), starts[k], 20000);
    const auto l = drift<Leapfrog, double>(leapfrog(cases[3], 0.01), starts[k], 10000);
    std::printf("case IV start %zu, h = 0.01, t = 100: order 8 H %.2e I_case4 %.2e (h = 0.005: H "
                "%.2e I %.2e); leapfrog H %.2e I_case4 %.2e\n",
                k + 1, f[0], f[1], f2[0], f2[1], l[0], l[1]);
    EXPECT_LT(std::max(f[0], f[1]), 2e-9);
    EXPECT_LT(std::max(f2[0], f2[1]), 1e-11);
    EXPECT_GT(std::min(l[0], l[1]), 1e4 * std::max(f[0], f[1]));
  }
}

TEST(Flow, DetectsEachCaseAndNone) {
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto c = flow(cases[i], 0.1);
    EXPECT_EQ(Flow::detected_case(c), static_cast<int>(i + 1));
    EXPECT_EQ(Flow::case_name(c), names[i]);
    EXPECT_EQ(Flow::invariant_names(c),
              (std::vector<std::string>{"H", "I_case" + std::to_string(i + 1)}));
  }
  const auto none = [](const Potential& v) {
    const auto c = flow(v, 0.1);
    EXPECT_EQ(Flow::detected_case(c), 0);
    EXPECT_EQ(Flow::case_name(c), "none");
    EXPECT_EQ(Flow::invariant_names(c), (std::vector<std::string>{"H"}));
  };
  none(generic);
  none({A0, 0.3, a0, a0, 1.0});               // β = α, δ arbitrary: not integrable
  none({A0, 0.3, a0, a0 * (1 + 1e-9), 2 * a0});  // beyond the 1e-12 tolerance
  none({A0, 0.3, 0, 0, 1});                   // α = 0 with δ ≠ 0
  none({A0, 0.3, 0, 1, 0});                   // separable, but none of the four cases
  none({A0, 0.3, a0, 16 * a0, 12 * a0});      // case III's couplings with B ≠ 4A
  // Within the tolerance.
  EXPECT_EQ(Flow::detected_case(flow({A0, 0.3, a0, a0 * (1 + 5e-13), 2 * a0}, 0.1)), 1);
  EXPECT_EQ(Flow::detected_case(flow({A0, A0 * (1 + 5e-13), a0, a0, 6 * a0}, 0.1)), 2);
  EXPECT_EQ(Flow::detected_case(flow({A0, 0.3, -0.4, -0.4, -0.8}, 0.1)), 1);  // α < 0
  EXPECT_EQ(Leapfrog::detected_case(leapfrog(cases[2], 0.1)), 3);
}

TEST(Flow, OnlyHWhenNoCaseHolds) {
  const auto c = flow({A0, 0.3, a0, a0, 1.0}, 0.1);
  double out[2] = {0, -12345};
  Flow::invariants(c, starts[1], out);
  const auto& x = starts[1];
  const double H = 0.5 * (x[2] * x[2] + x[3] * x[3]) + A0 * x[0] * x[0] + 0.3 * x[1] * x[1] +
                   a0 * std::pow(x[0], 4) + a0 * std::pow(x[1], 4) + x[0] * x[0] * x[1] * x[1];
  EXPECT_NEAR(out[0], H, 1e-15);
  EXPECT_EQ(out[1], -12345);  // not written
}

TEST(Flow, DegenerateSetsFollowTheDocumentedRule) {
  const auto& x = starts[1];
  const double L = x[0] * x[3] - x[1] * x[2];
  // The linear set satisfies every case: case I, I_case1 = p1²/2 + A q1², for any B.
  for (double B : {0.3, A0, 4 * A0}) {
    const auto c = flow({A0, B, 0, 0, 0}, 0.1);
    EXPECT_EQ(Flow::detected_case(c), 1) << B;
    double out[2];
    Flow::invariants(c, x, out);
    EXPECT_NEAR(out[1], 0.5 * x[2] * x[2] + A0 * x[0] * x[0], 1e-16) << B;
    // conserved by the flow (the q1 oscillator's energy), to O(h⁸)
    EXPECT_LT((drift<Flow, double>(flow({A0, B, 0, 0, 0}, 0.01), x, 10000)[1]), 1e-13) << B;
  }
  // Case I with A = B: the (B − A)/α term vanishes, I_case1 = L².
  const auto c = flow({0.5, 0.5, a0, a0, 2 * a0}, 0.1);
  double out[2];
  Flow::invariants(c, x, out);
  EXPECT_NEAR(out[1], L * L, 1e-16);
}

TEST(Flow, ReversedRunReturnsToStartWithinTolerance) {
  const auto back_and_forth = [](const auto& model, const auto& c) {
    using M = std::decay_t<decltype(model)>;
    for (const auto& x : starts) {
      auto s = M::reversed(c, run<M>(c, x, 1000));
      s = M::reversed(c, run<M>(c, s, 1000));
      for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(s[k], x[k], 1e-12) << M::name << k;
    }
  };
  for (const auto& v : {cases[3], generic}) {
    for (double order : {2.0, 4.0, 6.0, 8.0}) back_and_forth(Flow{}, flow(v, 0.05, order));
    back_and_forth(Leapfrog{}, leapfrog(v, 0.05));
  }
  const auto r = Flow::reversed(flow(generic, 0.1), Flow::State<double>{1, 2, 0.0, -0.0});
  EXPECT_TRUE(std::signbit(r[2]));
  EXPECT_FALSE(std::signbit(r[3]));
  EXPECT_EQ(r[0], 1);
}

TEST(Flow, ConversionsTimeAndEscapeMeasure) {
  const auto c = flow(generic, 0.1);
  const Phase x{0.3, -0.2, 0.1, 0.4};
  const auto s = Flow::from_phase_space(c, x, Start::euler);
  EXPECT_EQ(s, (std::array{0.3, -0.2, 0.1, 0.4}));
  EXPECT_EQ(Flow::from_phase_space(c, x, Start::taylor), s);
  const Phase y = Flow::to_phase_space(c, s);
  EXPECT_EQ((std::array{y.q1, y.q2, y.p1, y.p2}), s);
  EXPECT_EQ(Flow::time(c, 250, s), 250 * 0.1);
  EXPECT_EQ(Flow::escape_measure(s), std::fma(-0.2, -0.2, 0.3 * 0.3));
}

// {I, H} from central differences of the kernel's own invariants, in long double.
long double bracket(const Flow::Coeffs& c, const std::array<long double, 4>& z,
                    long double (*I)(const Flow::Coeffs&, const std::array<long double, 4>&),
                    long double& scale) {
  const auto H = [&](const std::array<long double, 4>& s) {
    long double out[2] = {};
    Flow::invariants(c, s, out);
    return out[0];
  };
  std::array<long double, 4> dI, dH;
  const long double eps = 1e-6L;
  for (std::size_t k = 0; k < 4; ++k) {
    auto up = z, down = z;
    up[k] += eps;
    down[k] -= eps;
    dI[k] = (I(c, up) - I(c, down)) / (2 * eps);
    dH[k] = (H(up) - H(down)) / (2 * eps);
  }
  scale = std::hypot(std::hypot(dI[0], dI[1]), std::hypot(dI[2], dI[3])) *
          std::hypot(std::hypot(dH[0], dH[1]), std::hypot(dH[2], dH[3]));
  return dI[0] * dH[2] - dI[2] * dH[0] + dI[1] * dH[3] - dI[3] * dH[1];
}

long double kernel_I(const Flow::Coeffs& c, const std::array<long double, 4>& s) {
  long double out[2] = {};
  Flow::invariants(c, s, out);
  return out[1];
}

// Case III's integral as printed in the paper: α where 2α belongs, erratum E1 (docs/maps.md §9).
long double printed_I3(const Flow::Coeffs& c, const std::array<long double, 4>& s) {
  const long double q1 = s[0], q2 = s[1], p1 = s[2], p2 = s[3];
  return (q1 * p2 - q2 * p1) * p1 + 2 * q1 * q1 * q2 * (c.A + c.alpha * (q1 * q1 + 2 * q2 * q2));
}

TEST(Flow, SecondIntegralsPoissonCommuteWithHWithinTolerance) {
  // 20 random points and parameter sets; |{I, H}| relative to |∇I||∇H|.
  std::mt19937_64 rng(2024);
  std::cout << "[ seed ] 2024\n";
  std::uniform_real_distribution<double> u(-0.6, 0.6), pos(0.2, 1.5), coupling(-1.0, 1.0);
  const std::array<std::string_view, 7> labels = {"I",      "II",          "III",      "IV",
                                                  "I, A=B", "linear",      "linear A=B"};
  std::array<double, 7> worst{};
  double printed = 0;  // the largest relative misfit of {I_printed, H} to its closed form
  for (int trial = 0; trial < 20; ++trial) {
    const double A = pos(rng), B = pos(rng), a = coupling(rng);
    const std::array<long double, 4> z = {u(rng), u(rng), u(rng), u(rng)};
    const std::array<Potential, 7> sets = {{{A, B, a, a, 2 * a},
                                            {A, A, a, a, 6 * a},
                                            {A, 4 * A, a, 16 * a, 12 * a},
                                            {A, 4 * A, a, 8 * a, 6 * a},
                                            {A, A, a, a, 2 * a},
                                            {A, B, 0, 0, 0},
                                            {A, A, 0, 0, 0}}};
    for (std::size_t k = 0; k < sets.size(); ++k) {
      const auto c = flow(sets[k], 0.1);
      ASSERT_NE(Flow::detected_case(c), 0);
      long double scale;
      const double r = static_cast<double>(std::fabs(bracket(c, z, kernel_I, scale)) / scale);
      worst[k] = std::max(worst[k], r);
      EXPECT_LE(r, 1e-9) << labels[k] << ", trial " << trial;
    }
    // The printed case III integral: {I, H} = −2αq1(4p1q1²q2 + 4p1q2³ + p2q1³ + 6p2q1q2²) ≠ 0.
    long double scale;
    const long double pb = bracket(flow(sets[2], 0.1), z, printed_I3, scale);
    const long double q1 = z[0], q2 = z[1], p1 = z[2], p2 = z[3];
    const long double closed = -2 * a * q1 *
                               (4 * p1 * q1 * q1 * q2 + 4 * p1 * q2 * q2 * q2 + p2 * q1 * q1 * q1 +
                                6 * p2 * q1 * q2 * q2);
    printed = std::max(printed, static_cast<double>(std::fabs(pb - closed) / scale));
    EXPECT_GT(std::fabs(closed), 1e-6L * scale) << "trial " << trial;
  }
  std::printf("max |{I, H}| / (|grad I| |grad H|):");
  for (std::size_t k = 0; k < labels.size(); ++k)
    std::printf(" %s %.1e;", std::string(labels[k]).c_str(), worst[k]);
  std::printf(" printed case III minus its closed form: %.1e\n", printed);
  EXPECT_LE(printed, 1e-9);
}

}  // namespace
}  // namespace qmaps
