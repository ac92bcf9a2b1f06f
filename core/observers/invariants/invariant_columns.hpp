#pragma once
// Invariant k's columns in an ensemble (invariant_track.hpp): its values at the orbits' start and
// their max |I_n − I_0|.
#include <cstddef>

#include "core/ensemble.hpp"
#include "core/observers/lane_observers.hpp"

namespace qmaps {

inline const AlignedArray<double>& invariant_initial(const Ensemble& e, std::size_t k) {
  return e.columns_of(lane_index<InvariantTrack>)[2 * k];
}
inline const AlignedArray<double>& invariant_drift(const Ensemble& e, std::size_t k) {
  return e.columns_of(lane_index<InvariantTrack>)[2 * k + 1];
}

}  // namespace qmaps
