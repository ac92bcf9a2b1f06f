#pragma once
// Case III (β = 16α, δ = 12α, B = 4A) through the Levi-Civita map and a fictitious time s;
// docs/maps.md §7, with errata E12–E15, E17 (docs/maps.md §9).
//
//   q1 = u1u2, q2 = (u1² − u2²)/2, r² = u1² + u2² = 2|q|, dt = r² ds, λ = H(q0, p0) per orbit.
//   Each u_k (k = 1, 2) follows its own two-step scheme; with v = u_{k,n−1}, u = u_{k,n},
//   w = u_{k,n+1} and c = ds²:
//     (w − 2u + v)/c = 2λu − 2Au³(w² + wv + v²) − 2αu⁵(w⁴ + w³v + w²v² + wv³ + v⁴)
//   a quartic P(w) = 0 solved by Halley's method, Δw = P P′/(P′² − P P″/2), from the
//   Störmer–Verlet predictor w0 = 2u − v + c(2λu − 6Au⁵ − 10αu⁹): two corrections, then more
//   until both components' |Δw| ≤ 2⁻²⁰(1 + |w|). A lane stops exactly where the scalar path
//   stops. Faults are escapes: no convergence in 40 corrections, P′ = 0 or P′² − P P″/2 = 0 at an
//   iterate, or P′ ≤ 0 at the root (not the branch through 2u − v, where P′ → 1).
//   Physical time: t_{n+2} = t_{n+1} + ds(r²_{n+1} + r²_{n+2})/2 (t_order = 2, trapezoid) or
//   t_{n+1} + ds r²_{n+1} (t_order = 1, the paper's left rule).
//   Invariants: I_k = ½((w − u)/ds)² − λuw + A u³w³ + α u⁵w⁵ on (u, w) = (u_{k,n}, u_{k,n+1});
//   I_1 is the discrete counterpart of the continuous second integral, I_1 + I_2 ≈ 0 to O(ds²).
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "core/dual.hpp"
#include "core/escape.hpp"
#include "core/error.hpp"
#include "core/ops.hpp"
#include "core/map_concept.hpp"
#include "core/params.hpp"
#include "core/phase.hpp"
#include "core/potential.hpp"

namespace qmaps::kernels {

struct Case3 {
  static constexpr std::string_view name = "case3";
  static constexpr std::string_view summary =
      "case III (beta = 16 alpha, delta = 12 alpha, B = 4A), Levi-Civita map, fictitious time";
  static constexpr std::string_view equations =
      "(levi), (hamilton-case3-trans), (case3-separation), (case3-discrete), (d-var-change); "
      "invariants I_k (errata E12-E15, E17)";
  static constexpr std::string_view invariant_summary = "I_1, I_2";
  static constexpr std::array<ParamSpec, 4> params = {{
      {"A", "coefficient of q1^2 (and B = 4A of q2^2)"},
      {"alpha", "quartic coupling (beta = 16 alpha, delta = 12 alpha)"},
      {"ds", "fictitious-time step, > 0"},
      {"t_order", "physical-time rule: 2 trapezoid, 1 left point (the paper's)", 2},
  }};
  static constexpr std::array<std::string_view, 7> state_names = {
      "u1_n", "u2_n", "u1_n+1", "u2_n+1", "t_n", "t_n+1", "lambda"};
  template <class V>
  using State = std::array<V, 7>;
  static constexpr std::size_t max_invariants = 2;
  static constexpr bool time_per_orbit = true;
  static constexpr std::array<std::size_t, 2> clock_state = {4, 5};  // t_n, t_n+1
  static constexpr bool reports_faults = true;
  static constexpr MapFacts facts = {
      .example = {{{"A", 0.7}, {"alpha", 0.9}, {"ds", 0.1}}},
      .escaping = {{{"A", 0.7}, {"alpha", -0.4}, {"ds", 0.1}}},
      .step = "ds", .order = 2,
      .reversal_tolerance = 1e-10, .drift_tolerance = 1e-10,  // measured 2.6e-11, 1.1e-11
      .preset = "case3", .slow = true,
      .volume_preserving = false, .forces_per_step = 0, .speed_budget = 0.1};
  static constexpr int max_iterations = 40;

  struct Coeffs {
    double A, alpha, ds;
    double c, two_Ac, two_alphac, six_Ac, ten_alphac;  // ds², 2A ds², 2α ds², 6A ds², 10α ds²
    double inv_ds, half_ds;
    bool trapezoid;
  };

  static Coeffs coefficients(std::span<const double> p) {
    const double A = p[0], alpha = p[1], ds = p[2], order = p[3];
    check_step(name, "ds", ds);
    if (order != 1 && order != 2)
      throw usage_error("case3: t_order must be 1 (left point) or 2 (trapezoid), got " +
                        number_text(order));
    const double c = ds * ds;
    return {A,      alpha,  ds,   c, 2 * A * c, 2 * alpha * c, 6 * A * c, 10 * alpha * c,
            1 / ds, ds / 2, order == 2};
  }

  // The continuous system this map discretizes (docs/maps.md §1).
  static Potential continuous(const Coeffs& c) {
    return {c.A, 4 * c.A, c.alpha, 16 * c.alpha, 12 * c.alpha};
  }

  static std::vector<std::string> invariant_names(const Coeffs&) { return {"I_1", "I_2"}; }

  template <class V>
  static V step(const Coeffs& c, State<V>& s) {
    const V minus_2c_lambda = V(-2.0 * c.c) * s[6];
    const Quartic<V> p1(c, s[2], s[0], minus_2c_lambda), p2(c, s[3], s[1], minus_2c_lambda);
    V w1, w2;
    const V fault = solve(p1, p2, w1, w2);
    if constexpr (is_dual<V>) {  // the tangent map (core/dual.hpp)
      w1 = root_derivative(p1, w1);
      w2 = root_derivative(p2, w2);
    }
    const V r_next = radius2(s[2], s[3]), r_new = radius2(w1, w2);
    const V dt = c.trapezoid ? V(c.half_ds) * (r_next + r_new) : V(c.ds) * r_next;
    s = {s[2], s[3], w1, w2, s[5], s[5] + dt, s[6]};
    return fault;
  }

  // |q_{n+1}|² = r⁴/4 with r² = |u_{n+1}|²
  template <class V>
  static V escape_measure(const State<V>& s) {
    const V r2 = radius2(s[2], s[3]);
    return V(0.25) * (r2 * r2);
  }

  template <class V>
  static void invariants(const Coeffs& c, const State<V>& s, V* out) {
    for (int k = 0; k < 2; ++k) {
      const V u = s[k], w = s[2 + k], uw = u * w, uw3 = uw * uw * uw;
      const V p = (w - u) * V(c.inv_ds);
      out[k] = V(0.5) * p * p - s[6] * uw + V(c.A) * uw3 + V(c.alpha) * uw3 * uw * uw;
    }
  }

  // The continuous s-acceleration 2λu − 6Au⁵ − 10αu⁹ of one component.
  static double acceleration(const Coeffs& c, double lambda, double u) {
    const double u4 = u * u * u * u;
    return u * (2 * lambda - 6 * c.A * u4 - 10 * c.alpha * u4 * u4);
  }

  static State<double> from_phase_space(const Coeffs& c, const Phase& x, Start start) {
    const double q = std::hypot(x.q1, x.q2);
    double u1 = std::sqrt(q + x.q2), u2 = std::copysign(std::sqrt(q - x.q2), x.q1);
    if (std::fabs(u1) >= std::fabs(u2)) {  // the smaller component from q1 = u1u2, exactly
      if (u1 != 0) u2 = x.q1 / u1;
    } else {
      u1 = x.q1 / u2;
    }
    const double q1s = x.q1 * x.q1, q2s = x.q2 * x.q2;
    const double lambda = 0.5 * (x.p1 * x.p1 + x.p2 * x.p2) + c.A * (q1s + 4 * q2s) +
                          c.alpha * (q1s * q1s + 16 * q2s * q2s + 12 * q1s * q2s);
    const double P1 = u2 * x.p1 + u1 * x.p2, P2 = u1 * x.p1 - u2 * x.p2;
    double v1 = u1 + c.ds * P1, v2 = u2 + c.ds * P2;
    if (start == Start::taylor) {
      v1 += 0.5 * c.c * acceleration(c, lambda, u1);
      v2 += 0.5 * c.c * acceleration(c, lambda, u2);
    }
    const double r0 = u1 * u1 + u2 * u2, r1 = v1 * v1 + v2 * v2;
    const double t1 = c.trapezoid ? c.half_ds * (r0 + r1) : c.ds * r0;
    return {u1, u2, v1, v2, 0.0, t1, lambda};
  }

  // q_n = (u1u2, (u1² − u2²)/2)
  template <class V>
  static std::array<V, 2> position(const Coeffs&, const State<V>& s) {
    return {s[0] * s[1], V(0.5) * (s[0] * s[0] - s[1] * s[1])};
  }

  // The orbit's physical time t_n
  template <class V>
  static V clock(const State<V>& s) { return s[4]; }

  // q_n from u_n; p_n from P_n = (u_{n+1} − u_{n−1})/(2 ds), u_{n−1} by one reversed step.
  template <class V>
  static std::array<V, 4> phase(const Coeffs& c, const State<V>& s) {
    State<V> back = reversed(c, s);
    step(c, back);
    const V u1 = s[0], u2 = s[1], r2 = radius2(u1, u2), half(0.5), k(0.5 * c.inv_ds);
    const V P1 = (s[2] - back[2]) * k, P2 = (s[3] - back[3]) * k;
    return {u1 * u2, half * (u1 * u1 - u2 * u2), ops::fma(u2, P1, u1 * P2) / r2,
            ops::fms(u1, P1, u2 * P2) / r2};
  }
  static Phase to_phase_space(const Coeffs& c, const State<double>& s) {
    const auto x = phase(c, s);
    return {x[0], x[1], x[2], x[3]};
  }

  static double time(const Coeffs&, long long, const State<double>& s) { return s[4]; }

  // (u_{n+1}, u_n): P is symmetric in w ↔ v, so the same step retraces u. Time still advances
  // (retracing t needs ds → −ds).
  template <class V>
  static State<V> reversed(const Coeffs&, const State<V>& s) {
    return {s[2], s[3], s[0], s[1], s[5], s[4], s[6]};
  }

 private:
  template <class V>
  static V radius2(V a, V b) { return ops::fma(b, b, a * a); }

  // One component's quartic P(w) = (((c4 w + c3) w + c2) w + c1) w + c0 for u = u_{k,n},
  // v = u_{k,n−1} (the scheme times c, expanded in w), P′ and h = P″/2 as polynomials in w, and
  // the predictor. minus_2c_lambda = −2cλ is the orbit's, shared by both components.
  template <class V>
  struct Quartic {
    V c4, c3, c2, c1, c0;  // P
    V s3, s2, s1;          // P′ = ((s3 w + s2) w + s1) w + c1
    V h2;                  // h = (h2 w + s2) w + c2
    V guess;
    Quartic(const Coeffs& c, V u, V v, V minus_2c_lambda) {
      const V u2 = u * u, u4 = u2 * u2, u3 = u2 * u, u5 = u4 * u;
      const V a3 = V(c.two_Ac) * u3, a5 = V(c.two_alphac) * u5;
      const V v2 = v * v;
      const V r = ops::fma(minus_2c_lambda, u, v - (u + u));  // v − 2u − 2cλu
      c4 = a5;
      c3 = a5 * v;
      c2 = ops::fma(a5, v2, a3);
      c1 = ops::fma(c2, v, V(1.0));  // 1 + a3v + a5v³
      c0 = ops::fma(c2, v2, r);      // r + a3v² + a5v⁴
      // 4a5, 3c3, 2c2 and 6a5 by exact doublings and one rounded sum each (= the products)
      const V two_a5 = a5 + a5;
      s3 = two_a5 + two_a5;
      s2 = c3 + (c3 + c3);
      s1 = c2 + c2;
      h2 = s3 + two_a5;
      // Störmer–Verlet: 2u − v + c(2λu − 6Au⁵ − 10αu⁹) = −(r + u⁵(6Ac + 10αc u⁴))
      guess = ops::neg(ops::fma(ops::fma(V(c.ten_alphac), u4, V(c.six_Ac)), u5, r));
    }
    // Halley's correction Δ = P P′ / (P′² − P h) at w, and P′ there, in Horner's form. A zero
    // divisor gives an infinite or NaN Δ, which never settles; a zero P′ gives Δ = 0, and the
    // iterate stays where P′ = 0.
    struct Correction {
      V delta, slope;
    };
    Correction halley(V w) const {
      const V value = ops::fma(ops::fma(ops::fma(ops::fma(c4, w, c3), w, c2), w, c1), w, c0);
      const V slope = ops::fma(ops::fma(ops::fma(s3, w, s2), w, s1), w, c1);
      const V h = ops::fma(ops::fma(h2, w, s2), w, c2);
      return {value * slope / ops::fms(slope, slope, value * h), slope};
    }
  };

  // |Δw| ≤ 2⁻²⁰(1 + |w|) for the new iterate w
  // The derivative of the root w of P(w; u, v, λ) = 0 by the implicit-function rule,
  // dw = −(∂P/∂(u, v, λ))·d(u, v, λ)/P′(w): one more correction in Dual arithmetic at the root,
  // where P = 0, has exactly that derivative. Its value moves by round-off and is not kept, so
  // the tangent step's values stay the plain step's bits.
  template <class V>
  static V root_derivative(const Quartic<V>& p, const V& w) {
    V settled_root = w - p.halley(w).delta;
    settled_root.v = w.v;
    return settled_root;
  }

  template <class V>
  static ops::mask_t<V> settled(V delta, V w) {
    const V tol(0x1p-20);
    return ops::abs(delta) <= ops::fma(tol, ops::abs(w), tol);
  }

  // Halley on both components: two corrections on every lane, then more on the lanes where either
  // |Δw| > 2⁻²⁰(1 + |w|). Convergence is cubic, e_{k+1} ≈ K e_k³ with K = |h²/P′² − P‴/(6P′)| =
  // O(ds²), so the error left after a correction of 2⁻²⁰ is below round-off. Returns the fault
  // codes. They are read at the end: a lane whose Δ was infinite or NaN has not settled, and a
  // lane that met P′ = 0 is still at that iterate.
  template <class V>
  static V solve(const Quartic<V>& p1, const Quartic<V>& p2, V& w1, V& w2) {
    using Mask = ops::mask_t<V>;
    w1 = p1.guess;
    w2 = p2.guess;
    V slope1, slope2;
    Mask done;
    for (int it = 0; it < 2; ++it) {
      const auto d1 = p1.halley(w1), d2 = p2.halley(w2);
      w1 = w1 - d1.delta;
      w2 = w2 - d2.delta;
      slope1 = d1.slope;
      slope2 = d2.slope;
      const Mask settled1 = settled(d1.delta, w1), settled2 = settled(d2.delta, w2);
      done = settled1 & settled2;  // both evaluated: a mask, not a short circuit
    }
    Mask active = ops::negate(done);
    for (int it = 2; it < max_iterations && ops::any(active); ++it) {
      const auto d1 = p1.halley(w1), d2 = p2.halley(w2);
      const V n1 = w1 - d1.delta, n2 = w2 - d2.delta;
      w1 = ops::select(active, n1, w1);
      w2 = ops::select(active, n2, w2);
      slope1 = ops::select(active, d1.slope, slope1);
      slope2 = ops::select(active, d2.slope, slope2);
      const Mask settled1 = settled(d1.delta, n1), settled2 = settled(d2.delta, n2);
      active = active & ops::negate(settled1 & settled2);
    }
    const V none(0.0);
    const Mask uphill1 = slope1 > none, uphill2 = slope2 > none;
    const Mask uphill = uphill1 & uphill2;
    if (ops::all(uphill & ops::negate(active))) return none;
    const V on_branch = ops::select(uphill, none, V(double(EscapeReason::wrong_branch)));
    const Mask flat1 = slope1 == none, flat2 = slope2 == none;
    const V flat = ops::select(flat1 | flat2, V(double(EscapeReason::zero_derivative)), on_branch);
    return ops::select(active, V(double(EscapeReason::no_convergence)), flat);
  }
};

}  // namespace qmaps::kernels
