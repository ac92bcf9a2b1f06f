#pragma once
// The continuous flow of H = ½|p|² + A q1² + B q2² + α q1⁴ + β q2⁴ + δ q1²q2² (docs/maps.md §1),
// integrated by explicit symplectic compositions of Störmer–Verlet; the state is (q1, q2, p1, p2)
// at t = nh.
//
//   F1 = −2q1 (A + 2α q1² + δ q2²),   F2 = −2q2 (B + 2β q2² + δ q1²)          (q'' = F)
//   S(τ) = D(τ/2) K(τ) D(τ/2),   K(τ): p += τ F(q),   D(τ): q += τ p           (drift-kick-drift)
//   one step = S(γ_1 h) ⋯ S(γ_s h), adjacent half-drifts merged:
//     D(γ_1 h/2) K(γ_1 h) D((γ_1+γ_2) h/2) K(γ_2 h) ⋯ K(γ_s h) D(γ_s h/2)
//   s kicks and s + 1 drifts, so s force evaluations per step:
//
//   order  s   γ_1 … γ_s                                            forces per step
//     2    1   1                                  (leapfrog)        1
//     4    3   w1 w0 w1, w1 = 1/(2 − 2^{1/3})     (Yoshida)         3
//     6    7   w3 … w1 w0 w1 … w3                 (Yoshida 1990 A)  7
//     8   15   w7 … w1 w0 w1 … w7                 (Yoshida 1990 A)  15
//   with w0 = 1 − 2(w1 + … + wm). Solution A of order 8 has a large error constant: in the tests
//   its error at t = 1 exceeds order 6's down to h ≈ 1/140 (7.9e-12 against 1.7e-12 at h = 1/64).
//
// Invariants: H, and the second integral of the case the parameters satisfy (docs/maps.md §1),
// with 2α in case III by erratum E1 (docs/maps.md §9), L = q1p2 − q2p1:
//   I   β = α, δ = 2α            I_case1 = L² + (B−A)/α · {p1² + 2q1²[A + α(q1²+q2²)]}
//   II  β = α, δ = 6α, B = A     I_case2 = p1p2 + 2q1q2[A + 2α(q1²+q2²)]
//   III β = 16α, δ = 12α, B = 4A I_case3 = L p1 + 2q1²q2[A + 2α(q1²+2q2²)]
//   IV  β = 8α, δ = 6α, B = 4A   I_case4 = 4αq1²(q1p2 − 2q2p1)² + {p1² + 2q1²[A + α(q1²+2q2²)]}²
//
// Hénon's method carries a phase point to the plane q_k = value (a section of mode exact): with
// q_k as the independent variable σ the flow is dq/dσ = p/p_k, dp/dσ = F(q)/p_k. Split as a step
// is split, both parts are solved exactly, j being the other index:
//   D(τ): q_j += τ p_j/p_k, q_k += τ          K(τ): q fixed, p_k' = sgn(p_k) √(p_k² + 2τF_k),
//                                                    p_j += 2τF_j/(p_k + p_k')
// and composed with the step's own γ_i over Δσ = value − q_k: the point lies on the plane to
// round-off, accurate to the composition's order. Where p_k vanishes on the way the result is
// not finite.
//
// A relation x = y holds when |x − y| ≤ 1e-12 max(|x|, |y|); the integral is then that of the exact
// relation, written in A and α (and B for case I). For α ≠ 0 the cases exclude one another; only
// the linear set α = β = δ = 0 satisfies several, and it is case I (the first that holds) with
// I_case1 = p1²/2 + A q1² (an integral for every A, B; for A ≠ B the limit α → 0 of
// α I_case1/(2(B − A))), since (B−A)/α is undefined there.
// A = B needs no rule: the (B−A)/α term vanishes and I_case1 = L². No case holds: H alone.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/ops.hpp"
#include "core/map_concept.hpp"
#include "core/params.hpp"
#include "core/phase.hpp"
#include "core/potential.hpp"

namespace qmaps::kernels {

namespace detail {

// w1 … wm of the compositions of order 4, 6 and 8 (Yoshida, Phys. Lett. A 150, 262 (1990)).
inline constexpr std::array<double, 1> yoshida4 = {1.3512071919596576340};
inline constexpr std::array<double, 3> yoshida6 = {-0.117767998417887e1, 0.235573213359357,
                                                   0.784513610477560};
inline constexpr std::array<double, 7> yoshida8 = {
    -0.161582374150097e1, -0.244699182370524e1, -0.716989419708120e-2, 0.244002732616735e1,
    0.157739928123617,    0.182020630970714e1,  0.104242620869991e1};

inline constexpr std::array<ParamSpec, 6> flow_params = {{
    {"A", "coefficient of q1^2 in the potential"},
    {"B", "coefficient of q2^2 in the potential"},
    {"alpha", "coefficient of q1^4"},
    {"beta", "coefficient of q2^4"},
    {"delta", "coefficient of q1^2 q2^2"},
    {"h", "time step, > 0"},
}};

// Everything Flow and Leapfrog share: they differ only in the composition chosen.
struct SplitFlow {
  static constexpr std::array<std::string_view, 4> state_names = {"q1", "q2", "p1", "p2"};
  template <class V>
  using State = std::array<V, 4>;
  static constexpr std::size_t max_invariants = 2;
  static constexpr bool time_per_orbit = false;
  static constexpr bool reports_faults = false;

  struct Coeffs {
    double A, B, alpha, beta, delta, h;
    int order, stages;               // s
    std::array<double, 16> drift;    // q += drift[i] p before kick i; drift[s] ends the step
    std::array<double, 15> kick;     // p += kick[i] F(q): γ_i h
    std::array<double, 16> drift_unit;  // (γ_i + γ_{i+1})/2 and γ_i: the composition over a unit
    std::array<double, 15> kick_unit;   // step, for Hénon's method
    double fA, fB, fa, fb, fd;       // F1 = q1(fA + fa q1² + fd q2²), F2 = q2(fB + fb q2² + fd q1²)
    int which;                       // detected case, 0 = none
    bool linear;                     // α = β = δ = 0: I_case1 = p1²/2 + A q1²
    double kI;                       // (B − A)/α (case I, α ≠ 0)
  };

  static int detected_case(const Coeffs& c) { return c.which; }
  static std::string_view case_name(const Coeffs& c) {
    constexpr std::array<std::string_view, 5> names = {"none", "I", "II", "III", "IV"};
    return names[static_cast<std::size_t>(c.which)];
  }

  // The continuous system this map discretizes (docs/maps.md §1).
  static Potential continuous(const Coeffs& c) {
    return {c.A, c.B, c.alpha, c.beta, c.delta};
  }

  static std::vector<std::string> invariant_names(const Coeffs& c) {
    if (c.which == 0) return {"H"};
    return {"H", "I_case" + std::to_string(c.which)};
  }

  template <class V>
  static void step(const Coeffs& c, State<V>& s) {
    V q1 = s[0], q2 = s[1], p1 = s[2], p2 = s[3];
    for (int i = 0;; ++i) {
      const V d(c.drift[static_cast<std::size_t>(i)]);
      q1 = ops::fma(d, p1, q1);
      q2 = ops::fma(d, p2, q2);
      if (i == c.stages) break;
      const V x1 = q1 * q1, x2 = q2 * q2, k(c.kick[static_cast<std::size_t>(i)]);
      p1 = ops::fma(k, q1 * ops::fma(V(c.fa), x1, ops::fma(V(c.fd), x2, V(c.fA))), p1);
      p2 = ops::fma(k, q2 * ops::fma(V(c.fb), x2, ops::fma(V(c.fd), x1, V(c.fB))), p2);
    }
    s = {q1, q2, p1, p2};
  }

  // Hénon's method (above): x = (q1, q2, p1, p2) carried until q_k has moved by ds.
  template <class V>
  static std::array<V, 4> to_plane(const Coeffs& c, const std::array<V, 4>& x, std::size_t k, V ds) {
    const std::size_t j = 1 - k;
    std::array<V, 2> q = {x[0], x[1]}, p = {x[2], x[3]}, F;
    const auto backward = p[k] < V(0.0);  // p_k keeps its sign on the way
    const V two(2.0);
    for (int i = 0;; ++i) {
      const V tau = V(c.drift_unit[static_cast<std::size_t>(i)]) * ds;
      q[j] = ops::fma(tau, p[j] / p[k], q[j]);
      q[k] = q[k] + tau;
      if (i == c.stages) break;
      const V x1 = q[0] * q[0], x2 = q[1] * q[1];
      const V tau2 = two * (V(c.kick_unit[static_cast<std::size_t>(i)]) * ds);
      F[0] = q[0] * ops::fma(V(c.fa), x1, ops::fma(V(c.fd), x2, V(c.fA)));
      F[1] = q[1] * ops::fma(V(c.fb), x2, ops::fma(V(c.fd), x1, V(c.fB)));
      const V root = ops::sqrt(ops::fma(tau2, F[k], p[k] * p[k]));
      const V pk = ops::select(backward, ops::neg(root), root);
      p[j] = ops::fma(tau2 / (p[k] + pk), F[j], p[j]);
      p[k] = pk;
    }
    return {q[0], q[1], p[0], p[1]};
  }

  template <class V>  // |q|²
  static V escape_measure(const State<V>& s) { return ops::fma(s[1], s[1], s[0] * s[0]); }

  template <class V>
  static void invariants(const Coeffs& c, const State<V>& s, V* out) {
    const V q1 = s[0], q2 = s[1], p1 = s[2], p2 = s[3], x1 = q1 * q1, x2 = q2 * q2;
    out[0] = V(0.5) * ops::fma(p2, p2, p1 * p1) + x1 * ops::fma(V(c.alpha), x1, V(c.A)) +
             x2 * ops::fma(V(c.beta), x2, V(c.B)) + V(c.delta) * (x1 * x2);
    const V L = ops::fms(q1, p2, q2 * p1), A(c.A), a(c.alpha), a2(2 * c.alpha), two(2.0);
    const V r2 = x1 + x2, w2 = ops::fma(two, x2, x1);  // q1² + q2², q1² + 2q2²
    if (c.which == 1 && c.linear) {
      out[1] = ops::fma(V(0.5) * p1, p1, A * x1);
    } else if (c.which == 1) {
      out[1] = ops::fma(L, L, V(c.kI) * ops::fma(two * x1, ops::fma(a, r2, A), p1 * p1));
    } else if (c.which == 2) {
      out[1] = ops::fma(p1, p2, two * (q1 * q2) * ops::fma(a2, r2, A));
    } else if (c.which == 3) {
      out[1] = ops::fma(L, p1, two * (x1 * q2) * ops::fma(a2, w2, A));
    } else if (c.which == 4) {
      const V M = ops::fms(q1, p2, two * (q2 * p1));
      const V K = ops::fma(two * x1, ops::fma(a, w2, A), p1 * p1);
      out[1] = ops::fma(V(4 * c.alpha) * x1, M * M, K * K);
    }
  }

  static State<double> from_phase_space(const Coeffs&, const Phase& x, Start) {
    return {x.q1, x.q2, x.p1, x.p2};
  }
  template <class V>
  static std::array<V, 2> position(const Coeffs&, const State<V>& s) { return {s[0], s[1]}; }
  template <class V>
  static std::array<V, 4> phase(const Coeffs&, const State<V>& s) { return s; }
  static Phase to_phase_space(const Coeffs&, const State<double>& s) {
    return {s[0], s[1], s[2], s[3]};
  }
  static double time(const Coeffs& c, long long n, const State<double>&) {
    return static_cast<double>(n) * c.h;
  }
  // (q, −p): every composition here is symmetric, so its steps from (q, −p) retrace s backward.
  template <class V>
  static State<V> reversed(const Coeffs&, const State<V>& s) {
    return {s[0], s[1], ops::neg(s[2]), ops::neg(s[3])};
  }

 protected:
  // p = (A, B, alpha, beta, delta, h); order ∈ {2, 4, 6, 8}.
  static Coeffs make(std::string_view map, std::span<const double> p, int order) {
    Coeffs c{};
    c.A = p[0], c.B = p[1], c.alpha = p[2], c.beta = p[3], c.delta = p[4], c.h = p[5];
    check_step(map, "h", c.h);
    const std::span<const double> w = order == 4 ? std::span<const double>(yoshida4)
                                      : order == 6 ? yoshida6
                                      : order == 8 ? yoshida8 : std::span<const double>();
    const std::size_t m = w.size(), s = 2 * m + 1;
    std::array<double, 17> g{};  // 0, γ_1 … γ_s, 0
    double sum = 0;
    for (std::size_t j = 1; j <= m; ++j) sum += (g[m + 1 - j] = g[m + 1 + j] = w[j - 1]);
    g[m + 1] = 1 - 2 * sum;
    c.order = order, c.stages = static_cast<int>(s);
    for (std::size_t i = 0; i <= s; ++i) c.drift[i] = (g[i] + g[i + 1]) * c.h / 2;
    for (std::size_t i = 0; i < s; ++i) c.kick[i] = g[i + 1] * c.h;
    for (std::size_t i = 0; i <= s; ++i) c.drift_unit[i] = (g[i] + g[i + 1]) / 2;
    for (std::size_t i = 0; i < s; ++i) c.kick_unit[i] = g[i + 1];
    c.fA = -2 * c.A, c.fB = -2 * c.B, c.fa = -4 * c.alpha, c.fb = -4 * c.beta, c.fd = -2 * c.delta;

    const auto holds = [](double x, double y) {
      return std::fabs(x - y) <= 1e-12 * std::max(std::fabs(x), std::fabs(y));
    };
    const double a = c.alpha, b = c.beta, d = c.delta;
    const std::array<bool, 4> cases = {
        holds(b, a) && holds(d, 2 * a),
        holds(b, a) && holds(d, 6 * a) && holds(c.B, c.A),
        holds(b, 16 * a) && holds(d, 12 * a) && holds(c.B, 4 * c.A),
        holds(b, 8 * a) && holds(d, 6 * a) && holds(c.B, 4 * c.A)};
    c.which = 0;
    for (int k = 4; k >= 1; --k)
      if (cases[static_cast<std::size_t>(k - 1)]) c.which = k;  // the first case that holds
    c.linear = c.which == 1 && a == 0;
    if (c.which == 1 && !c.linear) {
      c.kI = (c.B - c.A) / a;
      if (!std::isfinite(c.kI))
        throw usage_error(std::string(map) + ": (B - A)/alpha of case I overflows (alpha = " +
                          number_text(a) + ")");
    }
    return c;
  }
};

}  // namespace detail

struct Flow : detail::SplitFlow {
  static constexpr std::string_view name = "flow";
  static constexpr std::string_view summary =
      "the continuous flow, Yoshida composition of Stormer-Verlet of order 2, 4, 6 or 8";
  static constexpr std::string_view equations =
      "(hamilton-cont), (cont-quartic); the second integrals of cases I-IV (erratum E1)";
  static constexpr std::string_view invariant_summary =
      "H, and I_caseN of the case I-IV the parameters satisfy";
  // Case I's parameters; H and I_case1 are conserved to the composition's order (h⁶ by default),
  // not exactly.
  static constexpr MapFacts facts = {
      .example = {{{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"beta", 0.9}, {"delta", 1.8}, {"h", 0.1}}},
      .escaping = {{{"A", 0.7}, {"B", 0.3}, {"alpha", -0.4}, {"beta", -0.4}, {"delta", 0.2},
                    {"h", 0.05}}},
      .step = "h", .order = 0,
      .reversal_tolerance = 1e-11, .drift_tolerance = 1e-4,  // measured 6.9e-6 (h = 0.1, order 6)
      .preset = "case4-flow", .slow = true,
      .volume_preserving = true, .forces_per_step = 7, .speed_budget = 0};  // 7: at order 6
  static constexpr std::array<ParamSpec, 7> params = [] {
    std::array<ParamSpec, 7> p{};
    std::copy(detail::flow_params.begin(), detail::flow_params.end(), p.begin());
    // 6: order 8's large error constant makes it the less accurate above h ≈ 1/140 (above).
    p[6] = {"order", "order of the composition: 2, 4, 6 or 8", 6};
    return p;
  }();

  static Coeffs coefficients(std::span<const double> p) {
    const double order = p[6];
    if (order != 2 && order != 4 && order != 6 && order != 8)
      throw usage_error("flow: order must be 2, 4, 6 or 8 (got " + number_text(order) + ")");
    return make(name, p, static_cast<int>(order));
  }
};

struct Leapfrog : detail::SplitFlow {
  static constexpr std::string_view name = "leapfrog";
  static constexpr std::string_view summary =
      "the continuous flow, Stormer-Verlet (drift-kick-drift), order 2";
  static constexpr std::string_view equations = Flow::equations;
  static constexpr std::string_view invariant_summary = Flow::invariant_summary;
  // Case I's parameters; H and I_case1 oscillate at O(h²) about their initial values.
  static constexpr MapFacts facts = {
      .example = Flow::facts.example, .escaping = Flow::facts.escaping,
      .step = "h", .order = 2,
      .reversal_tolerance = 1e-11, .drift_tolerance = 0.15,  // measured 3.1e-2
      .preset = "leapfrog", .slow = false,
      .volume_preserving = true, .forces_per_step = 1, .speed_budget = 0};
  static constexpr std::array<ParamSpec, 6> params = detail::flow_params;

  static Coeffs coefficients(std::span<const double> p) { return make(name, p, 2); }
};

}  // namespace qmaps::kernels
