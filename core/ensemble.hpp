#pragma once
// An ensemble of orbits as structure of arrays: one aligned column per state component, orbits
// contiguous within it, padded to a whole number of the widest blocks. Beside the state: each
// orbit's escape record and its invariant tracking (value at step 0, max |I_n − I_0| so far).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/aligned_array.hpp"
#include "core/escape.hpp"

namespace qmaps {


struct Ensemble {
  // Widest block of the runner: 8 lanes × 8 chains. Every block size divides it.
  static constexpr std::size_t padding = 64;

  Ensemble(std::size_t orbits, std::size_t state_size, std::size_t invariants);

  std::size_t orbits;
  std::size_t padded;                              // orbits rounded up to `padding`
  std::vector<AlignedArray<double>> state;         // [component][orbit]
  AlignedArray<std::int64_t> escape_step;          // step whose state escaped; −1: never
  AlignedArray<std::uint8_t> escape_reason;        // EscapeReason
  std::vector<AlignedArray<double>> invariant_initial;    // [invariant][orbit]
  std::vector<AlignedArray<double>> invariant_max_drift;  // [invariant][orbit]
  long long step = 0;                              // the step the state is at

  // Orbit j of `from` (its state, escape record and invariant tracking) as orbit i.
  void set_orbit(std::size_t i, const Ensemble& from, std::size_t j);
  // Copies the last orbit into the padding lanes, so that every lane holds a valid state.
  void fill_padding();
  std::size_t escaped() const;
};

}  // namespace qmaps
