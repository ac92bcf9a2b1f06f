#pragma once
// A block's lanes in the ensemble: W orbits of a state-major ensemble loaded into one V, stored
// back, tested alive, and their escapes recorded; and one step that reports the lanes' faults.
#include <array>
#include <cstddef>
#include <tuple>

#include "core/ensemble.hpp"
#include "core/escape.hpp"
#include "core/ops.hpp"

namespace qmaps::detail {

// One step in place; returns the lanes' fault codes (0: none; always 0 for explicit maps).
template <class Map, class V>
V step_reporting_faults(const typename Map::Coeffs& c, typename Map::template State<V>& s) {
  if constexpr (Map::reports_faults) {
    return Map::step(c, s);
  } else {
    Map::step(c, s);
    return V(0.0);
  }
}

template <class Map, class V>
struct Lanes {
  using State = typename Map::template State<V>;
  using Mask = ops::mask_t<V>;
  static constexpr std::size_t W = ops::lanes<V>;

  static State load(const Ensemble& e, std::size_t orbit) {
    State s;
    for (std::size_t k = 0; k < s.size(); ++k) s[k] = ops::load<V>(&e.state[k][orbit]);
    return s;
  }
  static void store(Ensemble& e, std::size_t orbit, const State& s) {
    for (std::size_t k = 0; k < s.size(); ++k) ops::store(&e.state[k][orbit], s[k]);
  }
  // The lanes that hold a real orbit that has not escaped (padding lanes count as escaped).
  static Mask alive(const Ensemble& e, std::size_t orbit) {
    alignas(64) std::array<double, W> flags;
    for (std::size_t l = 0; l < W; ++l)
      flags[l] = orbit + l < e.orbits && e.escape_step[orbit + l] < 0 ? 1.0 : 0.0;
    return ops::load<V>(flags.data()) != V(0.0);
  }
  static State select(Mask m, const State& a, const State& b) {
    State s;
    for (std::size_t k = 0; k < s.size(); ++k) s[k] = ops::select(m, a[k], b[k]);
    return s;
  }
  // Records the escape at step n of the lanes in `fresh`, whose escaped state is `t` and whose
  // solver fault codes are `fault`.
  static void record(Ensemble& e, std::size_t orbit, long long n, Mask fresh, const State& t,
                     V fault) {
    const auto lanes = ops::lanes_of(fresh);
    const auto faults = ops::lanes_of(fault);
    std::array<std::array<double, W>, std::tuple_size_v<State>> values;
    for (std::size_t k = 0; k < t.size(); ++k) values[k] = ops::lanes_of(t[k]);
    for (std::size_t l = 0; l < W; ++l) {
      if (!lanes[l]) continue;
      std::array<double, std::tuple_size_v<State>> lane;
      for (std::size_t k = 0; k < t.size(); ++k) lane[k] = values[k][l];
      e.escape_step[orbit + l] = n;
      e.escape_reason[orbit + l] = escape_reason(faults[l], lane);
    }
  }
};

}  // namespace qmaps::detail
