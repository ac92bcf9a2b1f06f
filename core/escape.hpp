#pragma once
// Why an orbit stopped: the codes stored per orbit in /escape/reason. A map whose step solves an
// equation reports codes 3-5 itself; the runner finds 1 and 2.
#include <cstdint>
#include <span>
#include <string_view>

namespace qmaps {

enum class EscapeReason : std::uint8_t {
  none = 0,
  non_finite = 1,    // a state component became NaN or infinite
  beyond_bound = 2,  // the configuration left the ball |q| ≤ escape_bound
  no_convergence = 3,   // an implicit step's solver did not converge
  zero_derivative = 4,  // an implicit step's solver derivative vanished
  wrong_branch = 5,     // an implicit step's root is not on the physical branch
  singular = 6,         // a formula map's linear equations for q_{n+1} are singular
};
inline constexpr std::uint8_t last_escape_reason = 6;
std::string_view escape_reason_name(EscapeReason reason);
// Why a state (its components, one orbit) escaped: the solver's fault code when it is not 0,
// else non-finite, else beyond the bound.
// Out of line on purpose: the per-ISA translation units must not emit shared inline code.
std::uint8_t escape_reason(double fault, std::span<const double> state);

}  // namespace qmaps
