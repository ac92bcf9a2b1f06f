#pragma once
// An ensemble of orbits as structure of arrays: one aligned column per state component, orbits
// contiguous within it, padded to a whole number of the widest blocks. Beside the state: each
// orbit's escape record and its invariant tracking (value at step 0, max |I_n − I_0| so far).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "core/aligned_array.hpp"

namespace qmaps {

enum class EscapeReason : std::uint8_t {
  none = 0,
  non_finite = 1,    // a state component became NaN or infinite
  beyond_bound = 2,  // the configuration left the ball |q| ≤ escape_bound
  no_convergence = 3,   // an implicit step's solver did not converge
  zero_derivative = 4,  // an implicit step's solver derivative vanished
  wrong_branch = 5,     // an implicit step's root is not on the physical branch
};
std::string_view escape_reason_name(EscapeReason reason);
// Why a state (its components, one orbit) escaped: the solver's fault code when it is not 0,
// else non-finite, else beyond the bound.
// Out of line on purpose: the per-ISA translation units must not emit shared inline code.
std::uint8_t escape_reason(double fault, std::span<const double> state);

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

  // Copies the last orbit into the padding lanes, so that every lane holds a valid state.
  void fill_padding();
  std::size_t escaped() const;
};

}  // namespace qmaps
