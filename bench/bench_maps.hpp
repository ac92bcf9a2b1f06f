#pragma once
// The maps every benchmark and peer steps, at the parameters of their case (A = 0.7, alpha = 0.9,
// step 0.1; flow and leapfrog at the case IV set), and how many steps one iteration takes.
#include <span>
#include <string>

#include "bench_ensemble.hpp"
#include "core/params.hpp"

namespace qmaps {

struct BenchMap {
  const char* map;
  ParamValues params;
  bool slow;  // solves an equation per step (case3) or evaluates many forces (flow at order 8)
  long long steps() const { return slow ? bench_size().slow_steps : bench_size().steps; }
};

inline const ParamValues suris_params = {{"A", 0.7}, {"B", 0.3}, {"alpha", 0.9}, {"h", 0.1}};

inline std::span<const BenchMap> bench_maps() {
  static const BenchMap maps[] = {
      {"suris", suris_params, false},
      {"case2", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}}, false},
      {"case2-staggered", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}}, false},
      {"case2-hky", {{"A", 0.7}, {"alpha", 0.9}, {"h", 0.1}, {"gamma11", 0.6}, {"gamma21", 0.3}},
       false},
      {"case3", {{"A", 0.7}, {"alpha", 0.9}, {"ds", 0.1}}, true},
      {"flow",
       {{"A", 0.7}, {"B", 2.8}, {"alpha", 0.9}, {"beta", 7.2}, {"delta", 5.4}, {"h", 0.1},
        {"order", 8}},
       true},
      {"leapfrog",
       {{"A", 0.7}, {"B", 2.8}, {"alpha", 0.9}, {"beta", 7.2}, {"delta", 5.4}, {"h", 0.1}}, false},
  };
  return maps;
}

}  // namespace qmaps
