#pragma once
// The maps every benchmark steps: each map of kernels/maps.hpp at its example parameters, and how
// many steps one iteration takes.
#include <span>
#include <string>
#include <vector>

#include "bench_ensemble.hpp"
#include "core/params.hpp"
#include "kernels/catalogue.hpp"
#include "kernels/suris.hpp"

namespace qmaps {

struct BenchMap {
  std::string map;
  ParamValues params;
  bool slow;  // solves an equation per step (case3) or evaluates many forces (flow: 7 at order 6)
  int forces_per_step;  // MapFacts': 0 where the map is not a splitting
  double speed_budget;  // MapFacts': its least rate against Suris'; 0: none
  long long steps() const { return slow ? bench_size().slow_steps : bench_size().steps; }
};

inline std::span<const BenchMap> bench_maps() {
  static const std::vector<BenchMap> maps = [] {
    std::vector<BenchMap> out;
    for (const MapEntry& m : catalogue())
      out.push_back({std::string(m.name), param_values(m.facts->example), m.facts->slow,
                     m.facts->forces_per_step, m.facts->speed_budget});
    return out;
  }();
  return maps;
}

inline const ParamValues suris_params = param_values(kernels::Suris::facts.example);

}  // namespace qmaps
