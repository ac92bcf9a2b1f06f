#pragma once
// Chaos indicators of an orbit from its tangent map (core/dual.hpp): a deviation vector w is
// advanced with the state by the map's own step, its growth measured and w renormalized to 1
// every step. With δ_k = |w_k| after step k (over the phase-space part, the state's first four
// components; w_0 of norm 1) and n steps:
//
//   L_n     = Σ_{k≤n} ln δ_k                    the log of the deviation's growth
//   λ_n     = L_n / n                           the largest Lyapunov exponent, per step
//   FLI_n   = max_{k≤n} L_k                     the fast Lyapunov indicator
//   Y_n     = (2/n) Σ_{k≤n} k ln δ_k            MEGNO for maps
//   ⟨Y⟩_n   = (1/n) Σ_{k≤n} Y_k                 its mean: → 2 on quasi-periodic orbits,
//                                               → 0 on stable periodic ones, ≈ λ n / 2 on chaotic
//
// (docs/chaos.md). Everything is computed in V through core/ops, so a batch's lanes give the
// scalar path's bits.
#include <algorithm>
#include <array>
#include <cstddef>

#include "core/chaos_sums.hpp"
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

// w /= |w| (over the phase-space part); returns |w|.
template <class V, std::size_t S>
V normalize(std::array<V, S>& w) {
  const V norm = ops::sqrt(phase_dot(w, w));
  for (auto& component : w) component = component / norm;
  return norm;
}

// Modified Gram–Schmidt over the phase-space part, in place and in order: w_i loses its
// projection on each of w_0 … w_{i−1} in turn, then norms[i] = |w_i| and w_i is normalized.
// The product of the norms is the volume the vectors span.
template <class V, std::size_t S, std::size_t N>
void gram_schmidt(std::array<std::array<V, S>, N>& w, std::array<V, N>& norms) {
  for (std::size_t i = 0; i < N; ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const V d = phase_dot(w[i], w[j]);
      for (std::size_t k = 0; k < S; ++k) w[i][k] = ops::neg(ops::fms(d, w[j][k], w[i][k]));
    }
    norms[i] = normalize(w[i]);
  }
}

// The sums' update for a step in which the deviation grew by δ = `norm`.
template <class V>
void add_growth(ChaosSums<V>& sums, V norm) {
  const V growth = ops::log(norm);
  sums.steps = sums.steps + V(1.0);
  sums.log_growth = sums.log_growth + growth;
  sums.fli = ops::max(sums.fli, sums.log_growth);
  sums.weighted = ops::fma(sums.steps, growth, sums.weighted);
  sums.megno_sum = sums.megno_sum + V(2.0) * sums.weighted / sums.steps;
}

// The spectrum and the GALIs need four deviation vectors each, the first four orthonormalized
// every step (Benettin: Σ ln of the Gram–Schmidt norms / n → λ_1 ≥ … ≥ λ_4), the other four only
// normalized (GALI_k: the volume their first k span, from Gram–Schmidt of copies).
//
//   λ_i,n   = (1/n) Σ_{k≤n} ln r_i,k     r_i,k: the i-th Gram–Schmidt norm after step k
//   GALI_k  = |ŵ_1 ∧ … ∧ ŵ_k|            ŵ_i: the deviations, each of norm 1
//
// For a map of det J = 1, Σ_i ln r_i,k = 0 to round-off each step: the spectrum sums to 0 and
// comes in pairs λ_1 = −λ_4, λ_2 = −λ_3 (symplectic). On a regular orbit of two degrees of
// freedom GALI_2 stays near a positive value and GALI_4 falls as a power of n; on a chaotic one
// both fall exponentially (GALI_2 as e^{−(λ_1 − λ_2)n}).
//
// One step of all of them: the state s and its nine deviations w (w[0] for λ, FLI and MEGNO, w[1…4]
// for the spectrum, w[5…8] for the GALIs) by the map's own step on Dual<V, 9>; `sums` and
// `logs` (Σ ln r_i) take the step. Returns the step's fault codes (0 for the explicit maps).
template <class Map, class V>
V chaos_step(const typename Map::Coeffs& c, typename Map::template State<V>& s,
             std::array<typename Map::template State<V>, 9>& w, ChaosSums<V>& sums,
             std::array<V, 4>& logs) {
  const V fault = tangent_step<Map, 9>(c, s, w);
  add_growth(sums, normalize(w[0]));
  std::array<typename Map::template State<V>, 4> spectrum;
  std::copy(w.begin() + 1, w.begin() + 5, spectrum.begin());
  std::array<V, 4> norms;
  gram_schmidt(spectrum, norms);
  for (std::size_t i = 0; i < 4; ++i) {
    logs[i] = logs[i] + ops::log(norms[i]);
    w[1 + i] = spectrum[i];
    normalize(w[5 + i]);
  }
  return fault;
}

// GALI_k of the deviations w[5…8] that chaos_step keeps.
template <class V, std::size_t S>
V gali(const std::array<std::array<V, S>, 9>& w, std::size_t k) {
  std::array<std::array<V, S>, 4> copy;
  std::copy(w.begin() + 5, w.end(), copy.begin());
  std::array<V, 4> norms;
  gram_schmidt(copy, norms);
  V volume = norms[0];
  for (std::size_t i = 1; i < k; ++i) volume = volume * norms[i];
  return volume;
}

}  // namespace qmaps
