#pragma once
// A trajectory ([[trajectory]]): time series of chosen orbits, every `every` steps, each orbit's
// step, time, phase point, the map's invariants, the continuous system's H and second integral
// ("_cont"), and its chaos indicators when the run records them (ensembles/io/trajectories.hpp
// records and writes them).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace qmaps {

struct Trajectory {
  std::string name;
  std::vector<std::size_t> orbits;  // the orbits recorded, in this order
  long long every = 1;
  // One row per orbit and recorded step while the orbit has not escaped, orbit by orbit.
  std::vector<std::int64_t> orbit, step;
  std::vector<std::string> columns;         // t, q1, q2, p1, p2, invariants, …
  std::vector<std::vector<double>> values;  // [column][row]

  // The most rows an orbit can give over `steps` steps.
  static long long rows_per_orbit(long long steps, long long every) { return steps / every + 2; }
  double rows(long long steps) const {
    return static_cast<double>(orbits.size()) * static_cast<double>(rows_per_orbit(steps, every));
  }
  double bytes(long long steps) const {
    return 8.0 * rows(steps) * static_cast<double>(2 + columns.size());
  }
};

}  // namespace qmaps
