#pragma once
// Case III (β = 16α, δ = 12α, B = 4A) through the Levi-Civita map and a fictitious time s;
// MAPS.md §3, with errata E12–E15.
//
//   q1 = u1u2, q2 = (u1² − u2²)/2, r² = u1² + u2² = 2|q|, dt = r² ds, λ = H(q0, p0) per orbit.
//   Each u_k (k = 1, 2) follows its own two-step scheme; with v = u_{k,n−1}, u = u_{k,n},
//   w = u_{k,n+1} and c = ds²:
//     (w − 2u + v)/c = 2λu − 2Au³(w² + wv + v²) − 2αu⁵(w⁴ + w³v + w²v² + wv³ + v⁴)
//   a quartic P(w) = 0 solved by Newton from the Störmer–Verlet predictor
//   w0 = 2u − v + c(2λu − 6Au⁵ − 10αu⁹), until |Δw| ≤ 2⁻⁴³(1 + |w|), then one more correction.
//   A lane stops exactly where the scalar path stops. Faults are escapes: no convergence in 40
//   iterations, P' = 0, or P'(w) ≤ 0 at the root (not the branch through 2u − v, where P' → 1).
//   Physical time: t_{n+2} = t_{n+1} + ds(r²_{n+1} + r²_{n+2})/2 (t_order = 2, trapezoid) or
//   t_{n+1} + ds r²_{n+1} (t_order = 1, the paper's left rule).
//   Invariants: I_k = ½((w − u)/ds)² − λuw + A u³w³ + α u⁵w⁵ on (u, w) = (u_{k,n}, u_{k,n+1});
//   I_1 is the discrete counterpart of the continuous second integral, I_1 + I_2 ≈ 0 to O(ds²).
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "core/ensemble.hpp"
#include "core/error.hpp"
#include "core/ops.hpp"
#include "core/params.hpp"
#include "core/phase.hpp"

namespace qmaps::kernels {

struct Case3 {
  static constexpr std::string_view name = "case3";
  static constexpr std::string_view summary =
      "case III (beta = 16 alpha, delta = 12 alpha, B = 4A), Levi-Civita map, fictitious time";
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
  static constexpr int max_iterations = 40;

  struct Coeffs {
    double A, alpha, ds;
    double c, two_Ac, two_alphac;  // ds², 2A ds², 2α ds²
    double inv_ds, half_ds;
    bool trapezoid;
  };

  static Coeffs coefficients(std::span<const double> p) {
    const double A = p[0], alpha = p[1], ds = p[2], order = p[3];
    if (!(ds > 0)) throw usage_error("case3: ds must be > 0 (got " + number_text(ds) + ")");
    if (order != 1 && order != 2)
      throw usage_error("case3: t_order must be 1 (left point) or 2 (trapezoid), got " +
                        number_text(order));
    const double c = ds * ds;
    return {A, alpha, ds, c, 2 * A * c, 2 * alpha * c, 1 / ds, ds / 2, order == 2};
  }

  static std::vector<std::string> invariant_names(const Coeffs&) { return {"I_1", "I_2"}; }

  template <class V>
  static V step(const Coeffs& c, State<V>& s) {
    const V lambda = s[6];
    V fault(0.0);
    const V w1 = solve(c, s[2], s[0], lambda, fault);
    const V w2 = solve(c, s[3], s[1], lambda, fault);
    const V r_next = radius2(s[2], s[3]), r_new = radius2(w1, w2);
    const V dt = c.trapezoid ? V(c.half_ds) * (r_next + r_new) : V(c.ds) * r_next;
    s = {s[2], s[3], w1, w2, s[5], s[5] + dt, lambda};
    return fault;
  }

  template <class V>
  static V escape_measure(const State<V>& s) { return radius2(s[2], s[3]); }

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

  // q_n from u_n; p_n from P_n = (u_{n+1} − u_{n−1})/(2 ds), u_{n−1} by one reversed step.
  static Phase to_phase_space(const Coeffs& c, const State<double>& s) {
    State<double> back = reversed(c, s);
    step(c, back);
    const double u1 = s[0], u2 = s[1], r2 = u1 * u1 + u2 * u2;
    const double P1 = (s[2] - back[2]) * 0.5 * c.inv_ds, P2 = (s[3] - back[3]) * 0.5 * c.inv_ds;
    return {u1 * u2, 0.5 * (u1 * u1 - u2 * u2), (u2 * P1 + u1 * P2) / r2, (u1 * P1 - u2 * P2) / r2};
  }

  static double time(const Coeffs&, long long, const State<double>& s) { return s[4]; }

  // (u_{n+1}, u_n): P is symmetric in w ↔ v, so the same step retraces u. Time still advances
  // (retracing t needs ds → −ds).
  static State<double> reversed(const Coeffs&, const State<double>& s) {
    return {s[2], s[3], s[0], s[1], s[5], s[4], s[6]};
  }

 private:
  template <class V>
  static V radius2(V a, V b) { return ops::fma(b, b, a * a); }

  // The root w of P near the predictor, for u = u_{k,n}, v = u_{k,n−1}; sets `fault` (if still 0)
  // for the lanes that fail.
  template <class V>
  static V solve(const Coeffs& c, V u, V v, V lambda, V& fault) {
    using Mask = ops::mask_t<V>;
    const V u2 = u * u, u3 = u2 * u, u5 = u3 * u2;
    const V a3 = V(c.two_Ac) * u3, a5 = V(c.two_alphac) * u5;
    const V v2 = v * v, v3 = v2 * v, v4 = v2 * v2, three_v = V(3.0) * v, two_v2 = V(2.0) * v2;
    const V lu = lambda * u;
    const V r0 = v - V(2.0) * u - V(2.0 * c.c) * lu;  // P(w) = w + r0 + a3 S3(w) + a5 S5(w)
    const V u4 = u2 * u2;
    const V force = ops::fms(V(2.0), lu, u * u4 * (V(6.0 * c.A) + V(10.0 * c.alpha) * u4));
    V w = ops::fma(V(c.c), force, V(2.0) * u - v);

    Mask active = V(0.0) == V(0.0), last = V(0.0) != V(0.0);
    V slope(1.0);
    for (int it = 0; it < max_iterations && ops::any(active); ++it) {
      const V wv = w + v;
      const V S3 = ops::fma(w, wv, v2);
      const V S5 = ops::fma(w, ops::fma(w, ops::fma(w, wv, v2), v3), v4);
      const V P = ops::fma(a3, S3, ops::fma(a5, S5, w + r0));
      const V dS3 = ops::fma(V(2.0), w, v);
      const V dS5 = ops::fma(w, ops::fma(w, ops::fma(V(4.0), w, three_v), two_v2), v3);
      const V dP = ops::fma(a3, dS3, ops::fma(a5, dS5, V(1.0)));
      const Mask flat = active & (dP == V(0.0));
      fault = ops::select(flat & (fault == V(0.0)), V(double(EscapeReason::zero_derivative)), fault);
      active = active & ops::negate(flat);
      slope = ops::select(active, dP, slope);
      const V dw = P / dP, next = w - dw;
      w = ops::select(active, next, w);
      const Mask converged = ops::abs(dw) <= V(0x1p-43) * (V(1.0) + ops::abs(next));
      const Mask finished = active & last;
      last = last | (active & converged);
      active = active & ops::negate(finished);
    }
    const V none(0.0);
    fault = ops::select(active & (fault == none), V(double(EscapeReason::no_convergence)), fault);
    fault = ops::select(ops::negate(slope > none) & (fault == none),
                        V(double(EscapeReason::wrong_branch)), fault);
    return w;
  }
};

}  // namespace qmaps::kernels
