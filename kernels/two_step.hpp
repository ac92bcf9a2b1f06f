#pragma once
// What every two-step map shares (state (q_n, q_{n+1}), update symmetric under q_{n+1} ↔ q_{n−1}):
// reversal, the phase point with the central difference p_n = (q_{n+1} − q_{n−1})/(2h), q_{n−1}
// being one step of the reversed state, and the physical time n h. A map derives from
// TwoStep<Map> (its Coeffs has h) and gets these.
#include <array>

#include "core/phase.hpp"

namespace qmaps::kernels {

template <class Map>
struct TwoStep {
  // (q_{n+1}, q_n)
  template <class V>
  static std::array<V, 4> reversed(const auto&, const std::array<V, 4>& s) {
    return {s[2], s[3], s[0], s[1]};
  }

  // (q1, q2) at node n
  template <class V>
  static std::array<V, 2> position(const auto&, const std::array<V, 4>& s) {
    return {s[0], s[1]};
  }

  // (q1, q2, p1, p2) at node n
  template <class V>
  static std::array<V, 4> phase(const auto& c, const std::array<V, 4>& s) {
    auto back = reversed(c, s);
    Map::step(c, back);
    const V two_h(2 * c.h);
    return {s[0], s[1], (s[2] - back[2]) / two_h, (s[3] - back[3]) / two_h};
  }

  static Phase to_phase_space(const auto& c, const std::array<double, 4>& s) {
    const auto x = phase(c, s);
    return {x[0], x[1], x[2], x[3]};
  }

  static double time(const auto& c, long long n, const std::array<double, 4>&) {
    return static_cast<double>(n) * c.h;
  }
};

}  // namespace qmaps::kernels
