#pragma once
// Chaos indicators of an orbit from its tangent map (core/dual.hpp): deviation vectors advance
// with the state by the map's own step. Norms and products are over the phase-space part, the
// state's first four components. With u_n the first deviation after n steps (|u_0| = 1) and
// L_n = ln |u_n|, its growth (kept as L = base + ½ ln |u|², u rescaled to 1 only when |u|²
// leaves [2^-300, 2^300], so no step pays a square root or a division for it):
//
//   λ_n     = L_n / n                                the largest Lyapunov exponent, per step
//   FLI_n   = max_{k≤n} L_k                          the fast Lyapunov indicator
//   Y_n     = (2/n) Σ_{k≤n} k ln(|u_k|/|u_k−1|)      MEGNO for maps,
//           = 2 L_n − (2/n) Σ_{k<n} L_k              by Abel summation (one log per step)
//   ⟨Y⟩_n   = (1/n) Σ_{k≤n} Y_k                      its mean: → 2 on quasi-periodic orbits,
//                                                    → 0 on stable periodic ones, ≈ λ n/2 on chaotic
//
// The spectrum and the GALIs use eight more deviations. Four are orthonormalized by modified
// Gram–Schmidt every `every` steps (Benettin); with r_i the i-th norm at each of those steps,
//   λ_i,n   = (1/n) Σ ln r_i                         λ_1 ≥ … ≥ λ_4
// The other four are only normalized every `every` steps (against overflow); at the end
//   GALI_k  = σ_1 ⋯ σ_k                              of the matrix of their k first, normalized
// (core/gali.cpp). Where det J = 1, Σ_i ln r_i = 0 to round-off and the spectrum comes in pairs
// λ_1 = −λ_4, λ_2 = −λ_3. On a regular orbit GALI_2 stays near a positive value and GALI_4 falls
// as a power of n; on a chaotic one both fall exponentially (docs/chaos.md).
//
// Everything here is written once over V through core/ops, so a batch's lanes give the scalar
// path's bits.
#include <array>
#include <cstddef>

#include "core/dual.hpp"
#include "core/ops.hpp"

namespace qmaps {

// One step of the state s and N deviation vectors w (states of V) by the map's own step on
// Dual<V, N>. Returns the step's fault codes (0 for the explicit maps).
template <class Map, std::size_t N, class V>
V tangent_step(const typename Map::Coeffs& c, typename Map::template State<V>& s,
               std::array<typename Map::template State<V>, N>& w) {
  auto x = with_deviations<N>(s, w);
  V fault(0.0);
  if constexpr (Map::reports_faults)
    fault = Map::step(c, x).v;
  else
    Map::step(c, x);
  split(x, s, w);
  return fault;
}

// The dot product over the phase-space part (the state's first four components).
template <class V, std::size_t S>
V phase_dot(const std::array<V, S>& a, const std::array<V, S>& b) {
  V sum = a[0] * b[0];
  for (std::size_t k = 1; k < 4; ++k) sum = ops::fma(a[k], b[k], sum);
  return sum;
}

// w ·= 1/|w| where `due`; returns |w|.
template <class V, std::size_t S>
V normalize(std::array<V, S>& w, ops::mask_t<V> due) {
  const V norm = ops::sqrt(phase_dot(w, w));
  const V inverse = V(1.0) / norm;
  for (auto& component : w) component = ops::select(due, component * inverse, component);
  return norm;
}

// Modified Gram–Schmidt over the phase-space part, in order, where `due`: w_i loses its
// projection on each of the new w_0 … w_{i−1} in turn, then norms[i] = |w_i| and w_i is
// normalized. The product of the norms is the volume the vectors spanned.
template <class V, std::size_t S, std::size_t N>
void gram_schmidt(std::array<std::array<V, S>, N>& w, std::array<V, N>& norms,
                  ops::mask_t<V> due) {
  for (std::size_t i = 0; i < N; ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const V d = phase_dot(w[i], w[j]);
      for (std::size_t k = 0; k < S; ++k)
        w[i][k] = ops::select(due, ops::neg(ops::fms(d, w[j][k], w[i][k])), w[i][k]);
    }
    norms[i] = normalize(w[i], due);
  }
}

// The running sums of the first deviation (their definitions above).
template <class V>
struct Growth {
  V base, sum, fli, megno_sum, steps;  // L − ½ ln|u|², Σ_{k<n} L_k, FLI_n, Σ Y_k, n

  // L_n of the deviation u.
  template <std::size_t S>
  V log_growth(const std::array<V, S>& u) const {
    return ops::fma(V(0.5), ops::log(phase_dot(u, u)), base);
  }
  V lyapunov(V L) const { return L / steps; }
  V megno() const { return megno_sum / steps; }

  // The sums after a step that took the deviation to u (rescaled here when it must be).
  template <std::size_t S>
  void add_step(std::array<V, S>& u) {
    const V r2 = phase_dot(u, u);
    const auto far = (r2 > V(0x1p300)) | ((r2 < V(0x1p-300)) & (r2 > V(0.0)));
    if (ops::any(far)) [[unlikely]] {  // u → u/|u|, its log moved into base
      base = ops::select(far, ops::fma(V(0.5), ops::log(r2), base), base);
      normalize(u, far);
    }
    const V L = log_growth(u);
    steps = steps + V(1.0);
    const V Y = V(2.0) * (L - sum / steps);
    megno_sum = megno_sum + Y;
    sum = sum + L;
    fli = ops::max(fli, L);
  }
};

}  // namespace qmaps
