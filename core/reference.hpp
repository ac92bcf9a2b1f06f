#pragma once
// The scalar reference path: the kernel template at V = double, one orbit at a time, one step at a
// time, no threads. Every other path must reproduce it bit for bit.
#include <array>

#include "core/ensemble.hpp"
#include "core/run_plan.hpp"
#include "core/observers/tracking.hpp"

namespace qmaps {

template <class Map>
void advance_reference(const typename Map::Coeffs& c, Ensemble& e, const RunPlan& plan,
                       Observers* observers) {
  using State = typename Map::template State<double>;
  const double bound2 = plan.escape_bound2();
  const bool momentum = observers && observers->densities_need_momentum();
  const bool section_momentum = observers && observers->sections_need_momentum();
  for (std::size_t i = 0; i < e.orbits; ++i) {
    if (e.escape_step[i] >= 0) continue;
    State s;
    for (std::size_t k = 0; k < s.size(); ++k) s[k] = e.state[k][i];
    InvariantTrack<Map, double> track;
    track.load(e, i);
    std::array<double, 5> before{};
    if (observers) {
      if (plan.first == 0) sample_densities<Map>(c, s, true, *observers, momentum);
      if (!observers->sections.empty())
        before = node_values<Map>(c, s, section_momentum);
    }
    for (long long n = plan.first + 1; n <= plan.last; ++n) {
      State next = s;
      const double fault = step_reporting_faults<Map>(c, next);
      if (fault != 0 || !(Map::escape_measure(next) <= bound2)) {
        e.escape_step[i] = n;
        e.escape_reason[i] = escape_reason(fault, next);
        break;
      }
      s = next;
      if (observers) check_sections<Map>(c, s, true, *observers, section_momentum, i, n, before);
      if (plan.samples_at(n)) {
        if (plan.track_invariants) track.sample(c, s, true);
        if (observers) sample_densities<Map>(c, s, true, *observers, momentum);
      }
    }
    for (std::size_t k = 0; k < s.size(); ++k) e.state[k][i] = s[k];
    track.store(e, i);
  }
}

}  // namespace qmaps
