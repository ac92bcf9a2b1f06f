#include "core/escape.hpp"

#include <cmath>

namespace qmaps {

std::string_view escape_reason_name(EscapeReason reason) {
  switch (reason) {
    case EscapeReason::none: return "none";
    case EscapeReason::non_finite: return "non-finite";
    case EscapeReason::beyond_bound: return "beyond bound";
    case EscapeReason::no_convergence: return "solver did not converge";
    case EscapeReason::zero_derivative: return "solver derivative vanished";
    case EscapeReason::wrong_branch: return "solver root off the physical branch";
    case EscapeReason::singular: return "linear equations singular";
  }
  return "?";
}

std::uint8_t escape_reason(double fault, std::span<const double> state) {
  if (fault != 0) return static_cast<std::uint8_t>(fault);
  for (double x : state)
    if (!std::isfinite(x)) return static_cast<std::uint8_t>(EscapeReason::non_finite);
  return static_cast<std::uint8_t>(EscapeReason::beyond_bound);
}

}  // namespace qmaps
