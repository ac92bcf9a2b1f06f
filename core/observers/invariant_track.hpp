#pragma once
// The invariants' tracking of a block's lanes (or one orbit, V = double), held in registers
// while the block advances: the initial values and max |I_n − I_0| over the alive samples,
// loaded from and stored to the ensemble.
#include <cstddef>

#include "core/ensemble.hpp"
#include "core/ops.hpp"

namespace qmaps {

// One value's (a lane's or an orbit's) invariant tracking, held in registers while its block
// advances: the initial values and max |I_n − I_0| over the alive samples.
template <class Map, class V>
struct InvariantTrack {
  std::size_t count = 0;
  V initial[Map::max_invariants], drift[Map::max_invariants];

  void load(const Ensemble& e, std::size_t orbit) {
    count = e.invariant_max_drift.size();
    for (std::size_t k = 0; k < count; ++k) {
      initial[k] = ops::load<V>(&e.invariant_initial[k][orbit]);
      drift[k] = ops::load<V>(&e.invariant_max_drift[k][orbit]);
    }
  }
  void sample(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
              ops::mask_t<V> alive) {
    V values[Map::max_invariants];
    Map::invariants(c, s, values);
    for (std::size_t k = 0; k < count; ++k)
      drift[k] = ops::select(alive, ops::max(drift[k], ops::abs(values[k] - initial[k])), drift[k]);
  }
  void store(Ensemble& e, std::size_t orbit) const {
    for (std::size_t k = 0; k < count; ++k) ops::store(&e.invariant_max_drift[k][orbit], drift[k]);
  }
};

}  // namespace qmaps
