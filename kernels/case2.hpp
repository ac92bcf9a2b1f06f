#pragma once
// Case II (β = α, δ = 6α, B = A), symmetric map; docs/maps.md §4 and §5, errata E6–E8
// (docs/maps.md §9).
// u± = q1 ± q2 decouple case II into two oscillators ü = −2Au − 4αu³, each discretized as
// (decoupled_dis) (z − 2y + x)/h² = −2Ay − 2αy²(z + x), with x = u_{n−1}, y = u_n, z = u_{n+1}:
//
//   a = 1 − Ah², g = 2αh²:   z = 2a y/(1 + g y²) − x     (one division serves both oscillators)
//   q_{n+1} = ((z+ + z−)/2, (z+ − z−)/2)
//
// In q this is the corrected discrete-case2 (E6): (q1' − 2q1 + q1'')/h² = −2A q1
// − 4α(q1² + q2²)(q1' + q1'')/2 − 8α q1q2(q2' + q2'')/2, and the same with 1 ↔ 2.
//
// Invariants of a state (u, v) = (q_n, q_{n+1}), with d = v − u, P = u1v1 + u2v2,
// X = u1v2 + u2v1 and c2 = 2 − 2a (= 2Ah²):
//   K(x, y) = (y − x)² + c2 xy + g x²y²   (= x² + y² − 2a xy + g x²y², the oscillator's invariant)
//   H± = K(u±, v±)/(2h²) = ½p±² + A u±v± + α u±²v±²                        (Hamiltonian-dis)
//   I1 = (H+ + H−)/2 = [d1² + d2² + P(c2 + gP) + gX²]/(2h²)   → H                      (E7)
//   I2 = (H+ − H−)/2 = [2 d1d2 + X(c2 + 2gP)]/(2h²)            → p1p2 + 2q1q2[A + 2α|q|²]
// Every term is O(h²), where the literal x² + y² − 2a xy cancels O(1) terms; d± = d1 ± d2.
// c2 and g are the map's own rounded coefficients (2 − 2a is exact for ½ ≤ a ≤ 2) and 1/(2h²) is
// a common factor, so these are the invariants of the map as it is computed.
//
// Case2Staggered (docs/maps.md §5, E8): the paper's "asymmetric" discrete-case2-2 (with the E6
// factor) is this map for (q1_n, Q2_n), Q2_n := q2_{n−1} in the paper's indexing: the same
// arithmetic on the state (q1_n, q2_{n−1}, q1_{n+1}, q2_n). It starts with Q2_0 = q2(0), so the
// paper's q2_m ≈ q2(t_{m+1}): its q2_{n−1} is q2 at node n. H±, I1, I2 are invariant on this
// staggered pairing; on the naive one (q1_n, q2_n; q1_{n+1}, q2_{n+1}) they are not.
#include <array>
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

struct Case2 : TwoStep<Case2> {
  static constexpr std::string_view name = "case2";
  static constexpr std::string_view summary =
      "case II (beta = alpha, delta = 6 alpha, B = A), symmetric map through u = q1 +- q2";
  static constexpr std::string_view equations =
      "(osillators-decoupled), (decoupled_dis), (discrete-case2) corrected; invariants "
      "(Hamiltonian-dis), I1, I2 (errata E6, E7)";
  static constexpr std::string_view invariant_summary = "H1, H2, I1, I2";
  static constexpr bool time_per_orbit = false;
  static constexpr bool reports_faults = false;
  static constexpr MapFacts facts = {
      .example = {{{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}}},
      .escaping = {{{"A", 0.7}, {"alpha", -0.4}, {"h", 0.1}}},
      .step = "h", .order = 2,
      .reversal_tolerance = 1e-11, .drift_tolerance = 3e-11,
      .preset = "case2", .slow = false,
      .volume_preserving = true, .forces_per_step = 0, .speed_budget = 0.45};
  static constexpr std::array<ParamSpec, 3> params = {{
      {"A", "coefficient of q1^2 and of q2^2 (B = A)"},
      {"alpha", "quartic coupling: alpha (q1^4 + q2^4) + 6 alpha q1^2 q2^2"},
      {"h", "time step, > 0"},
  }};
  static constexpr std::array<std::string_view, 4> state_names = {"q1_n", "q2_n", "q1_n+1",
                                                                   "q2_n+1"};
  template <class V>
  using State = std::array<V, 4>;
  static constexpr std::size_t max_invariants = 4;

  struct Coeffs {
    double A, alpha, h;
    double two_a, g;     // 2(1 − Ah²), 2αh²: the update
    double c2, inv_2h2;  // 2 − 2a (2Ah² as the rounded map realises it), 1/(2h²)
  };

  static Coeffs coefficients(std::span<const double> p) { return make(name, p); }

  // The continuous system this map discretizes (docs/maps.md §1).
  static Potential continuous(const Coeffs& c) {
    return {c.A, c.A, c.alpha, c.alpha, 6 * c.alpha};
  }

  static std::vector<std::string> invariant_names(const Coeffs&) {
    return {"H1", "H2", "I1", "I2"};
  }

  template <class V>
  static void step(const Coeffs& c, State<V>& s) {
    // z± = 2a y±/D± − x±, with one division for both: 1/D± = D∓ / (D+ D−)
    const V yp = s[2] + s[3], ym = s[2] - s[3];
    const V Dp = ops::fma(V(c.g), yp * yp, V(1.0)), Dm = ops::fma(V(c.g), ym * ym, V(1.0));
    const V inv = V(1.0) / (Dp * Dm);
    const V zp = ops::fms(V(c.two_a) * yp, Dm * inv, s[0] + s[1]);
    const V zm = ops::fms(V(c.two_a) * ym, Dp * inv, s[0] - s[1]);
    s[0] = s[2];
    s[1] = s[3];
    s[2] = V(0.5) * (zp + zm);
    s[3] = V(0.5) * (zp - zm);
  }

  template <class V>
  static V escape_measure(const State<V>& s) { return ops::fma(s[3], s[3], s[2] * s[2]); }

  template <class V>
  static void invariants(const Coeffs& c, const State<V>& s, V* out) {
    const V u1 = s[0], u2 = s[1], v1 = s[2], v2 = s[3], d1 = v1 - u1, d2 = v2 - u2;
    const V P = ops::fma(u2, v2, u1 * v1), X = ops::fma(u2, v1, u1 * v2);
    const V g = V(c.g), c2 = V(c.c2), k = V(c.inv_2h2);
    out[0] = k * K(c, d1 + d2, (u1 + u2) * (v1 + v2));
    out[1] = k * K(c, d1 - d2, (u1 - u2) * (v1 - v2));
    out[2] = k * (ops::fma(d1, d1, d2 * d2) + ops::fma(g * X, X, P * ops::fma(g, P, c2)));
    out[3] = k * ops::fma(V(2.0) * d1, d2, X * ops::fma(V(2.0) * g, P, c2));
  }

  static State<double> from_phase_space(const Coeffs& c, const Phase& x, Start start) {
    return start_state(c.A, c.alpha, c.h, x, start);
  }

  // q_0 = q, q_1 = q + h p (+ (h²/2) F(q) for the taylor start), F = −∇V the continuous
  // acceleration of case II; shared with kernels/case2_hky.hpp.
  static State<double> start_state(double A, double alpha, double h, const Phase& x, Start start) {
    State<double> s{x.q1, x.q2, x.q1 + h * x.p1, x.q2 + h * x.p2};
    if (start == Start::taylor) {
      s[2] += 0.5 * h * h * (-2 * A * x.q1 - 4 * alpha * x.q1 * (x.q1 * x.q1 + 3 * x.q2 * x.q2));
      s[3] += 0.5 * h * h * (-2 * A * x.q2 - 4 * alpha * x.q2 * (x.q2 * x.q2 + 3 * x.q1 * x.q1));
    }
    return s;
  }


 protected:
  static Coeffs make(std::string_view map, std::span<const double> p) {
    const double A = p[0], alpha = p[1], h = p[2];
    const std::string who(map);
    check_step(who, "h", h);
    const double h2 = h * h, a = 1 - A * h2;
    if (a == 0) throw usage_error(who + ": 1 - A h^2 = 0: the map degenerates (A h^2 = 1)");
    return {A, alpha, h, 2 * a, 2 * alpha * h2, 2 - 2 * a, 1 / (2 * h2)};
  }

 private:
  // 2h²H of one oscillator from d = y − x and w = xy: d² + w(c2 + g w)
  template <class V>
  static V K(const Coeffs& c, V d, V w) {
    return ops::fma(d, d, w * ops::fma(V(c.g), w, V(c.c2)));
  }
};

// The same map and invariants; only what the components mean differs (see above).
struct Case2Staggered : Case2 {
  static constexpr std::string_view name = "case2-staggered";
  static constexpr std::string_view summary =
      "case II, the paper's asymmetric map: the symmetric map for (q1_n, q2_n-1)";
  static constexpr std::string_view equations =
      "(discrete-case2-2) with the factor of (discrete-case2); invariants of case2 on the "
      "staggered pairing (errata E6-E8)";
  static constexpr std::string_view invariant_summary =
      "H1, H2, I1, I2 (staggered pairing)";
  static constexpr MapFacts facts = {
      .example = Case2::facts.example, .escaping = Case2::facts.escaping,
      .step = "h", .order = 2,
      .reversal_tolerance = 1e-11, .drift_tolerance = 3e-11,
      .preset = "case2-staggered", .slow = false,
      .volume_preserving = true, .forces_per_step = 0, .speed_budget = 0};
  static constexpr std::array<std::string_view, 4> state_names = {"q1_n", "q2_n-1", "q1_n+1",
                                                                   "q2_n"};

  static Coeffs coefficients(std::span<const double> p) { return make(name, p); }
};

}  // namespace qmaps::kernels
