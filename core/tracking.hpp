#pragma once
// What both paths do to an orbit besides stepping it, written once for V = double and V = batch:
// sample its invariants (max |I_n − I_0| over the alive lanes) and classify an escape.
#include <cstddef>

#include "core/ensemble.hpp"
#include "core/ops.hpp"

namespace qmaps {

template <class Map, class V>
void sample_invariants(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
                       Ensemble& e, std::size_t orbit, ops::mask_t<V> alive) {
  V values[Map::max_invariants];
  Map::invariants(c, s, values);
  for (std::size_t k = 0; k < e.invariant_max_drift.size(); ++k) {
    const V initial = ops::load<V>(&e.invariant_initial[k][orbit]);
    double* drift_at = &e.invariant_max_drift[k][orbit];
    const V drift = ops::load<V>(drift_at);
    ops::store(drift_at, ops::select(alive, ops::max(drift, ops::abs(values[k] - initial)), drift));
  }
}


}  // namespace qmaps
