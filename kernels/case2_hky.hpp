#pragma once
// Case II (β = α, δ = 6α, B = A) with the general discrete oscillator of [HKY] applied to
// u± = q1 ± q2 (discrete-case3); docs/maps.md §6, errata E9–E11 (docs/maps.md §9). With
// x = u_{n−1}, y = u_n and z = u_{n+1}:
//
//   (z − 2y + x)/h² + 2A[c11 y + c12(z + x)] + 4α[c21 zyx + c22 y²(z + x)] = 0, i.e.
//   k3 xyz + (z + x)(k0 + k2 y²) − k1 y = 0,
//   k0 = 1 + 2Ah²c12, k1 = 2(1 − Ah²c11), k2 = 4αh²c22, k3 = 4αh²c21;
//   f = k0 + k2 y²,  z = (k1 y − x f)/(f + k3 xy)          (one division serves both oscillators)
//   q_{n+1} = ((z+ + z−)/2, (z+ − z−)/2)
//
// For any c's with k1 ≠ 0 (there is no integrability condition on them, E10) the oscillator keeps
//   K(x, y) = [(k1k2 + k0k3) x²y² + k0k1(x² + y²) − k1² xy] / [(k1 + k3x²)(k1 + k3y²)],
// whose numerator cancels O(1) terms down to O(h²); it is evaluated as
//   k1[(y − x)² + n0(x² + y²) + m1 xy] + (k1k2 + k0k3) x²y²,   n0 = k0 − 1, m1 = 2 − k1,
// with n0, m1 exact from the map's rounded k's (for ½ ≤ k0 ≤ 2, 1 ≤ k1 ≤ 4) and k1k2 + k0k3
// formed at the precision of V, so K is the invariant of the map as it is computed.
// K/h² → ½p² + A(c11 + 2c12)u² + α(c21 + 2c22)u⁴: the map approximates case II when
// c11 + 2c12 = 1 and c21 + 2c22 = 1 + O(h²) (consistency, not integrability).
//
// Invariants of (u, v) = (q_n, q_{n+1}): K± = K(u±, v±), E = K/h²,
//   I1 = (E+ + E−)/2 → H,   I2 = (E+ − E−)/2 → p1p2 + 2q1q2[A + 2α|q|²]
// (I2 is a difference: its absolute error is that of E±).
//
// Parameters: c11, c12, c21, c22, or [HKY]'s γ11, γ21 (γ11 + 2γ12 = 1, γ21 + γ22 = 1) with the
// paper's undefined "a" read as 2Ah² (E10): c11 = γ11, c12 = γ12, c21 = (1 − Ah²γ11)γ21,
// c22 = (1 + 2Ah²γ12)γ22/2. c = (1, 0, 0, ½) gives k0 = 1, k1 = 2a, k2 = 2αh², k3 = 0: the map
// of case2 (kernels/case2.hpp), with E± = H±/a.
#include <array>
#include <cmath>
#include <limits>
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
#include "kernels/case2.hpp"

namespace qmaps::kernels {

struct Case2Hky : TwoStep<Case2Hky> {
  static constexpr std::string_view name = "case2-hky";
  static constexpr std::string_view summary =
      "case II (beta = alpha, delta = 6 alpha, B = A), HKY oscillators through u = q1 +- q2";
  static constexpr std::string_view equations =
      "(discrete-case3) corrected, [HKY] oscillators; invariant K, [HKY]'s H1, H2 corrected "
      "(errata E9-E11)";
  static constexpr std::string_view invariant_summary = "K+, K-, I1, I2";
  static constexpr bool time_per_orbit = false;
  static constexpr bool reports_faults = false;
  static constexpr MapFacts facts = {
      .example = {{{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}, {"gamma11", 0.6}, {"gamma21", 0.3}}},
      .escaping = {{{"A", 0.7}, {"alpha", -0.4}, {"h", 0.1}, {"gamma11", 0.6}, {"gamma21", 0.3}}},
      .step = "h", .order = 2,
      .reversal_tolerance = 1e-11, .drift_tolerance = 3e-11,
      .preset = "case2-hky", .slow = false,
      .volume_preserving = false, .forces_per_step = 0, .speed_budget = 0.45};
  static constexpr double no_default = std::numeric_limits<double>::quiet_NaN();
  static constexpr std::array<ParamSpec, 9> params = {{
      {"A", "coefficient of q1^2 and of q2^2 (B = A)"},
      {"alpha", "quartic coupling: alpha (q1^4 + q2^4) + 6 alpha q1^2 q2^2"},
      {"h", "time step, > 0"},
      {"c11", "weight of 2A u_n (with c12, c21, c22; or give gamma11, gamma21)", no_default, true},
      {"c12", "weight of 2A (u_n+1 + u_n-1)", no_default, true},
      {"c21", "weight of 4 alpha u_n+1 u_n u_n-1", no_default, true},
      {"c22", "weight of 4 alpha u_n^2 (u_n+1 + u_n-1)", no_default, true},
      {"gamma11", "HKY's gamma11 (with gamma21, instead of the c's): c11 = gamma11", no_default,
       true},
      {"gamma21", "HKY's gamma21: c21 = (1 - A h^2 gamma11) gamma21", no_default, true},
  }};
  static constexpr std::array<std::string_view, 4> state_names = Case2::state_names;
  template <class V>
  using State = std::array<V, 4>;
  static constexpr std::size_t max_invariants = 4;

  struct Coeffs {
    double A, alpha, h;
    double c11, c12, c21, c22;  // as given, or from the gammas
    double k0, k1, k2, k3;      // the update
    double n0, m1, inv_h2;      // k0 − 1, 2 − k1, 1/h²
  };

  static Coeffs coefficients(std::span<const double> p) {
    const double A = p[0], alpha = p[1], h = p[2];
    check_step(name, "h", h);
    const double h2 = h * h;
    double c11 = p[3], c12 = p[4], c21 = p[5], c22 = p[6];
    const double gamma11 = p[7], gamma21 = p[8];
    const int cs = given(c11) + given(c12) + given(c21) + given(c22);
    const int gammas = given(gamma11) + given(gamma21);
    const std::string choice = "give either all of c11, c12, c21, c22 or both gamma11 and gamma21";
    if (cs > 0 && gammas > 0) throw usage_error("case2-hky: " + choice + ", not both sets");
    if (cs != 4 && gammas != 2)
      throw usage_error("case2-hky: " + choice + " (got " + std::to_string(cs) + " of the c's, " +
                        std::to_string(gammas) + " of the gammas)");
    if (gammas == 2) {
      const double gamma12 = (1 - gamma11) / 2, gamma22 = 1 - gamma21;
      c11 = gamma11;
      c12 = gamma12;
      c21 = (1 - A * h2 * gamma11) * gamma21;
      c22 = (1 + 2 * A * h2 * gamma12) * gamma22 / 2;
    }
    const double k0 = 1 + 2 * A * h2 * c12, k1 = 2 * (1 - A * h2 * c11);
    if (k1 == 0) throw usage_error("case2-hky: 1 - A h^2 c11 = 0: the map degenerates (k1 = 0)");
    return {A, alpha, h, c11, c12, c21, c22, k0, k1, 4 * alpha * h2 * c22, 4 * alpha * h2 * c21,
            k0 - 1, 2 - k1, 1 / h2};
  }

  // The continuous system this map discretizes (docs/maps.md §1).
  static Potential continuous(const Coeffs& c) {
    return {c.A, c.A, c.alpha, c.alpha, 6 * c.alpha};
  }

  static std::vector<std::string> invariant_names(const Coeffs&) {
    return {"K+", "K-", "I1", "I2"};
  }

  template <class V>
  static void step(const Coeffs& c, State<V>& s) {
    // z± = N± / D±, with one division for both: N± D∓ / (D+ D−)
    const V xp = s[0] + s[1], xm = s[0] - s[1], yp = s[2] + s[3], ym = s[2] - s[3];
    const V fp = ops::fma(V(c.k2), yp * yp, V(c.k0)), fm = ops::fma(V(c.k2), ym * ym, V(c.k0));
    const V Np = ops::fms(V(c.k1), yp, xp * fp), Dp = ops::fma(V(c.k3) * xp, yp, fp);
    const V Nm = ops::fms(V(c.k1), ym, xm * fm), Dm = ops::fma(V(c.k3) * xm, ym, fm);
    const V inv = V(1.0) / (Dp * Dm);
    const V zp = Np * Dm * inv, zm = Nm * Dp * inv;
    s[0] = s[2];
    s[1] = s[3];
    s[2] = V(0.5) * (zp + zm);
    s[3] = V(0.5) * (zp - zm);
  }

  template <class V>
  static V escape_measure(const State<V>& s) { return Case2::escape_measure(s); }

  template <class V>
  static void invariants(const Coeffs& c, const State<V>& s, V* out) {
    const V u1 = s[0], u2 = s[1], v1 = s[2], v2 = s[3], d1 = v1 - u1, d2 = v2 - u2;
    const V q4 = ops::fma(V(c.k1), V(c.k2), V(c.k0) * V(c.k3));
    out[0] = K(c, q4, u1 + u2, v1 + v2, d1 + d2);
    out[1] = K(c, q4, u1 - u2, v1 - v2, d1 - d2);
    const V half_inv_h2 = V(0.5) * V(c.inv_h2);
    out[2] = half_inv_h2 * (out[0] + out[1]);
    out[3] = half_inv_h2 * (out[0] - out[1]);
  }

  static State<double> from_phase_space(const Coeffs& c, const Phase& x, Start start) {
    return Case2::start_state(c.A, c.alpha, c.h, x, start);
  }


 private:
  static int given(double v) { return std::isnan(v) ? 0 : 1; }

  // K(x, y) with d = y − x and q4 = k1k2 + k0k3
  template <class V>
  static V K(const Coeffs& c, V q4, V x, V y, V d) {
    const V w = x * y, k1 = V(c.k1), k3 = V(c.k3);
    const V quadratic = ops::fma(d, d, ops::fma(V(c.n0), ops::fma(x, x, y * y), V(c.m1) * w));
    const V num = ops::fma(k1, quadratic, q4 * (w * w));
    return num / (ops::fma(k3, x * x, k1) * ops::fma(k3, y * y, k1));
  }
};

}  // namespace qmaps::kernels
