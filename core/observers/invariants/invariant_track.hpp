#pragma once
// The invariants' tracking, a lane measurement (core/observers/lane_observers.hpp): for each
// invariant I of the map, its value at the orbit's start and max |I_n − I_0| over the samples
// while the orbit stays alive; /invariants/<I>/initial and /invariants/<I>/max_abs_drift.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "core/ensemble.hpp"
#include "core/ops.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

template <class Map, class V>
struct InvariantTrack {
  using Columns = std::span<AlignedArray<double>>;
  using Read = std::span<const AlignedArray<double>>;

  // Invariant k's columns are 2k (initial) and 2k + 1 (drift). Always on.
  static std::vector<ColumnSpec> columns(const typename Map::Coeffs& c,
                                         std::span<const std::string>) {
    std::vector<ColumnSpec> specs;
    for (const auto& name : Map::invariant_names(c)) {
      specs.push_back({"invariants/" + name + "/initial"});
      specs.push_back({"invariants/" + name + "/max_abs_drift", 0.0});
    }
    return specs;
  }
  static void start(const typename Map::Coeffs& c, const typename Map::template State<double>& s,
                    Columns columns, std::size_t orbit) {
    double values[Map::max_invariants] = {};
    Map::invariants(c, s, values);
    for (std::size_t k = 0; k < columns.size() / 2; ++k) {
      columns[2 * k][orbit] = values[k];
      columns[2 * k + 1][orbit] = 0;
    }
  }

  // Past the map's invariants (count of max_invariants) the registers hold 0 and track nothing:
  // the sampling loop has a fixed trip count, unrolled.
  void load(Read columns, std::size_t orbit, const RunPlan&, std::size_t) {
    count = columns.size() / 2;
    for (std::size_t k = 0; k < Map::max_invariants; ++k) {
      initial[k] = k < count ? ops::load<V>(&columns[2 * k][orbit]) : V(0.0);
      drift[k] = k < count ? ops::load<V>(&columns[2 * k + 1][orbit]) : V(0.0);
    }
  }
  void sample(const typename Map::Coeffs& c, const typename Map::template State<V>& s,
              ops::mask_t<V> alive) {
    V values[Map::max_invariants];
    for (V& v : values) v = V(0.0);
    Map::invariants(c, s, values);
    for (std::size_t k = 0; k < Map::max_invariants; ++k)
      drift[k] = ops::select(alive, ops::max(drift[k], ops::abs(values[k] - initial[k])), drift[k]);
  }
  void store(Columns columns, std::size_t orbit) const {
    for (std::size_t k = 0; k < count; ++k) ops::store(&columns[2 * k + 1][orbit], drift[k]);
  }

  std::size_t count = 0;
  V initial[Map::max_invariants], drift[Map::max_invariants];
};

}  // namespace qmaps
