#pragma once
// An orbit's running chaos sums (their definitions: core/chaos.hpp): the steps n, L_n, FLI_n,
// Σ k ln δ_k and Σ Y_k, in V (double for one orbit, a batch for a block's lanes).
namespace qmaps {

template <class V>
struct ChaosSums {
  V steps = V(0.0), log_growth = V(0.0), fli = V(0.0), weighted = V(0.0), megno_sum = V(0.0);

  V lyapunov() const { return log_growth / steps; }  // λ_n, per step
  V megno() const { return megno_sum / steps; }      // ⟨Y⟩_n
};

}  // namespace qmaps
