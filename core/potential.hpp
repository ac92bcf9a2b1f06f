#pragma once
// The continuous system a map discretizes (docs/maps.md §1):
//   H = ½(p1² + p2²) + V(q),  V = A q1² + B q2² + α q1⁴ + β q2⁴ + δ q1²q2².
// Each kernel names its (A, B, α, β, δ); the `shell` ensemble solves H = E with it.
#include "core/phase.hpp"

namespace qmaps {

struct Potential {
  double A = 0, B = 0, alpha = 0, beta = 0, delta = 0;

  double value(double q1, double q2) const {
    const double x1 = q1 * q1, x2 = q2 * q2;
    return x1 * (A + alpha * x1) + x2 * (B + beta * x2) + delta * x1 * x2;
  }
  double energy(const Phase& x) const {
    return 0.5 * (x.p1 * x.p1 + x.p2 * x.p2) + value(x.q1, x.q2);
  }
};

}  // namespace qmaps
