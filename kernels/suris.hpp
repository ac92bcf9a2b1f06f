#pragma once
// Suris' map: the paper's case I (β = α, δ = 2α), discretization (b); docs/maps.md §3,
// errata E2–E5 (docs/maps.md §9). Discretization (a) solves to the same update. With
// x = q_{n−1}, y = q_n, z = q_{n+1}:
//
//   D  = 1 + 2αh²(y1² + y2²)
//   z1 = 2(1 − Ah²) y1 / D − x1,      z2 = 2(1 − Bh²) y2 / D − x2
//
// State (u, v) = (q_n, q_{n+1}), p = (v − u)/h, a = 1 − Ah², b = 1 − Bh², g = 2αh²:
//   H  = ½|p|² + A u1v1 + B u2v2 + α|u|²|v|²                          (disc-hamilton2)
//   I1 = v1² + u1² − 2a u1v1 + g u1²v1² + g/(a²−b²)·[a²(v1²u2² + u1²v2²) − 2ab u1u2v1v2]
//   I2 = the same with 1 ↔ 2, a ↔ b                                    (A ≠ B only; erratum E3)
//   I1 + I2 = 2h² H. I1 and I2 are evaluated in the algebraically equal, well-conditioned form
//   I1 = (v1−u1)² + 2Ah² u1v1 + g u1²v1² + g a²(X−Y)²/(a²−b²) + 2g a XY/(a+b), X = v1u2, Y = u1v2.
//   A = B: L = u1v2 − v1u2 = Y − X instead of I1, I2 (the discrete angular momentum).
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
#include "kernels/two_step.hpp"

namespace qmaps::kernels {

struct Suris : TwoStep<Suris> {
  static constexpr std::string_view name = "suris";
  static constexpr std::string_view summary =
      "case I (beta = alpha, delta = 2 alpha), Suris' discretization (b), identical to (a)";
  static constexpr std::string_view equations =
      "(disc-quarticb1/b2), identical to (disc-quartica1/2); invariants (disc-hamilton2), Suris' "
      "I1, I2 (errata E2-E5)";
  static constexpr std::string_view invariant_summary = "H, I1, I2 (A != B); H, L (A = B)";
  static constexpr bool time_per_orbit = false;
  static constexpr bool reports_faults = false;
  static constexpr MapFacts facts = {
      .example = {{{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}}},
      .escaping = {{{"A", 0.7}, {"B", 0.3}, {"alpha", -0.4}, {"h", 0.1}}},
      .step = "h", .order = 2,
      .reversal_tolerance = 1e-11, .drift_tolerance = 2e-11,
      .preset = "suris", .slow = false,
      .volume_preserving = true, .forces_per_step = 0, .speed_budget = 0};
  static constexpr std::array<ParamSpec, 4> params = {{
      {"A", "coefficient of q1^2 in the potential"},
      {"B", "coefficient of q2^2 in the potential"},
      {"alpha", "quartic coupling: alpha (q1^2 + q2^2)^2"},
      {"h", "time step, > 0"},
  }};
  static constexpr std::array<std::string_view, 4> state_names = {"q1_n", "q2_n", "q1_n+1",
                                                                   "q2_n+1"};
  template <class V>
  using State = std::array<V, 4>;
  static constexpr std::size_t max_invariants = 3;

  struct Coeffs {
    double A, B, alpha, h;
    double two_a, two_b, g;           // 2(1 − Ah²), 2(1 − Bh²), 2αh²
    double half_inv_h2, two_Ah2, two_Bh2;  // 1/(2h²), 2Ah², 2Bh²
    double HA, HB, Halpha;            // A, B, α as the rounded map realises them (for H)
    double k1, k2, kx1, kx2;          // g a²/(a²−b²), g b²/(b²−a²), 2g a/(a+b), 2g b/(a+b)
    bool has_I12;                     // A ≠ B
  };

  static Coeffs coefficients(std::span<const double> p) {
    const double A = p[0], B = p[1], alpha = p[2], h = p[3];
    check_step(name, "h", h);
    const double h2 = h * h, a = 1 - A * h2, b = 1 - B * h2;  // a, b: exact halves of 2a, 2b
    if (a == 0) throw usage_error("suris: 1 - A h^2 = 0: the map degenerates (A h^2 = 1)");
    if (b == 0) throw usage_error("suris: 1 - B h^2 = 0: the map degenerates (B h^2 = 1)");
    const double g = 2 * alpha * h2;
    // The invariants' coefficients come from the map's rounded ones (2 − 2a is exact), so the
    // invariants are those of the map as it is computed, not of a map one rounding away.
    Coeffs c{A, B, alpha, h, 2 * a, 2 * b, g, 0.5 / h2, 2 - 2 * a, 2 - 2 * b,
             (1 - a) / h2, (1 - b) / h2, g / (2 * h2), 0, 0, 0, 0, A != B};
    if (c.has_I12) {  // a² − b² = (a − b)(a + b), with a − b exact
      // I1 and I2 divide by a² − b²: where it rounds to 0 (|A − B| h² below about 2.2e-16, e.g.
      // h <= 1e-9, or A one ulp from B) or the quotients overflow, they cannot be evaluated.
      if (a == b || a == -b)
        throw usage_error("suris: A != B but (1 - A h^2)^2 - (1 - B h^2)^2 = 0 in double "
                          "precision (as when |A - B| h^2 < 2.2e-16): I1 and I2 divide by it "
                          "and cannot be evaluated; take A = B (invariants H, L), or A and B "
                          "further apart, or a larger h");
      c.k1 = g * a * a / ((a - b) * (a + b));
      c.k2 = g * b * b / ((b - a) * (a + b));
      c.kx1 = 2 * g * a / (a + b);
      c.kx2 = 2 * g * b / (a + b);
      if (!std::isfinite(c.k1) || !std::isfinite(c.k2) || !std::isfinite(c.kx1) ||
          !std::isfinite(c.kx2))
        throw usage_error("suris: the coefficients of I1 and I2, 2 alpha h^2 a^2/(a^2 - b^2) "
                          "with a = 1 - A h^2, b = 1 - B h^2, overflow: I1 and I2 cannot be "
                          "evaluated; take A = B, or A and B further apart, or a smaller alpha");
    }
    return c;
  }

  // The continuous system this map discretizes (docs/maps.md §1).
  static Potential continuous(const Coeffs& c) {
    return {c.A, c.B, c.alpha, c.alpha, 2 * c.alpha};
  }

  static std::vector<std::string> invariant_names(const Coeffs& c) {
    if (c.has_I12) return {"H", "I1", "I2"};
    return {"H", "L"};
  }

  template <class V>
  static void step(const Coeffs& c, State<V>& s) {
    const V y1 = s[2], y2 = s[3];
    const V inv = V(1.0) / ops::fma(V(c.g), norm2(y1, y2), V(1.0));
    const V z1 = ops::fms(V(c.two_a) * y1, inv, s[0]);
    const V z2 = ops::fms(V(c.two_b) * y2, inv, s[1]);
    s[0] = y1;
    s[1] = y2;
    s[2] = z1;
    s[3] = z2;
  }

  // |q_{n+1}|²: the runner's escape test, and the same expression as D's, so it costs nothing.
  template <class V>
  static V escape_measure(const State<V>& s) { return norm2(s[2], s[3]); }

  template <class V>
  static void invariants(const Coeffs& c, const State<V>& s, V* out) {
    // Shared by the three: d = v − u (= hp), w = (u1v1, u2v2), X = v1u2, Y = u1v2. Sums run in
    // the order of the formulas above, each product-and-add fused.
    const V u1 = s[0], u2 = s[1], v1 = s[2], v2 = s[3];
    const V d1 = v1 - u1, d2 = v2 - u2, e1 = d1 * d1, e2 = d2 * d2;
    const V w1 = u1 * v1, w2 = u2 * v2;
    const V kinetic = V(c.half_inv_h2) * (e1 + e2);  // ½|p|²
    out[0] = ops::fma(V(c.Halpha) * norm2(u1, u2), norm2(v1, v2),
                      ops::fma(V(c.HB), w2, ops::fma(V(c.HA), w1, kinetic)));
    const V X = v1 * u2, Y = u1 * v2;
    if (!c.has_I12) {
      out[1] = Y - X;
      return;
    }
    const V XmY = X - Y, cross = XmY * XmY, XY = X * Y;
    // (v−u)² + 2Ah² w + g w² = (v−u)² + w (2Ah² + g w)
    const V own1 = ops::fma(w1, ops::fma(V(c.g), w1, V(c.two_Ah2)), e1);
    const V own2 = ops::fma(w2, ops::fma(V(c.g), w2, V(c.two_Bh2)), e2);
    out[1] = ops::fma(V(c.kx1), XY, ops::fma(V(c.k1), cross, own1));
    out[2] = ops::fma(V(c.kx2), XY, ops::fma(V(c.k2), cross, own2));
  }

  // The continuous acceleration F(q) = −∇V.
  static std::array<double, 2> force(const Coeffs& c, double q1, double q2) {
    const double r2 = q1 * q1 + q2 * q2;
    return {-2 * c.A * q1 - 4 * c.alpha * q1 * r2, -2 * c.B * q2 - 4 * c.alpha * q2 * r2};
  }

  static State<double> from_phase_space(const Coeffs& c, const Phase& x, Start start) {
    State<double> s{x.q1, x.q2, x.q1 + c.h * x.p1, x.q2 + c.h * x.p2};
    if (start == Start::taylor) {
      const auto F = force(c, x.q1, x.q2);
      s[2] += 0.5 * c.h * c.h * F[0];
      s[3] += 0.5 * c.h * c.h * F[1];
    }
    return s;
  }


 private:
  template <class V>
  static V norm2(V a, V b) { return ops::fma(b, b, a * a); }
};

}  // namespace qmaps::kernels
