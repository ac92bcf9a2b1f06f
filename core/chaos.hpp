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
#include <array>
#include <cstddef>

#include "core/chaos_sums.hpp"
#include "core/dual.hpp"
#include "core/ops.hpp"

namespace qmaps {

// The initial deviation: (1, 1, 1, 1)/2 over the phase-space part, 0 elsewhere (case3's clock
// and energy).
template <class V, std::size_t S>
std::array<V, S> initial_deviation() {
  std::array<V, S> w;
  for (std::size_t k = 0; k < S; ++k) w[k] = V(k < 4 ? 0.5 : 0.0);
  return w;
}

// One step of the state s and its deviation w; the sums take the step's growth. Returns the
// step's fault codes (0 for the explicit maps).
template <class Map, class V>
V chaos_step(const typename Map::Coeffs& c, typename Map::template State<V>& s,
             typename Map::template State<V>& w, ChaosSums<V>& sums) {
  auto x = with_deviations<1>(s, std::array<typename Map::template State<V>, 1>{w});
  V fault(0.0);
  if constexpr (Map::reports_faults)
    fault = Map::step(c, x).v;
  else
    Map::step(c, x);
  std::array<typename Map::template State<V>, 1> deviation;
  split(x, s, deviation);
  w = deviation[0];
  V norm2 = w[0] * w[0];
  for (std::size_t k = 1; k < 4; ++k) norm2 = ops::fma(w[k], w[k], norm2);
  const V norm = ops::sqrt(norm2), growth = ops::log(norm);
  for (auto& component : w) component = component / norm;
  sums.steps = sums.steps + V(1.0);
  sums.log_growth = sums.log_growth + growth;
  sums.fli = ops::max(sums.fli, sums.log_growth);
  sums.weighted = ops::fma(sums.steps, growth, sums.weighted);
  sums.megno_sum = sums.megno_sum + V(2.0) * sums.weighted / sums.steps;
  return fault;
}

}  // namespace qmaps
