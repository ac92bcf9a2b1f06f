#pragma once
// Time series of chosen orbits ([[trajectory]]): every `every` steps, each orbit's step, time,
// phase point, the map's invariants, the continuous system's H and second integral ("_cont"), and
// its chaos indicators when the run records them. They are recorded when the run starts, by
// stepping copies of those orbits on the scalar reference path, which every path reproduces bit
// for bit; the file holds them under /trajectories/<name>/ (docs/hdf5-schema.md).
#include <cstdint>
#include <string>
#include <vector>

#include "core/ensemble.hpp"
#include "core/io/h5.hpp"
#include "core/model.hpp"
#include "core/run_plan.hpp"

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

// The column names every trajectory of this model has, and orbit i's row of them at e's step
// (`continuous` is continuous_model(model)): `qmaps orbit` prints the same rows.
std::vector<std::string> trajectory_columns(const Model& model);
std::vector<double> trajectory_row(const Model& model, const Model& continuous, const Ensemble& e,
                                   std::size_t i);
// Keeps, of each trajectory's orbits, those in [first, first + count), numbered from `first` (a
// shard's): a trajectory may be left with none.
void keep_orbits_in(std::vector<Trajectory>& trajectories, std::size_t first, std::size_t count);
// Fills t's rows from the started ensemble e (at step 0), over plan.total steps.
void record(Trajectory& t, const Model& model, const Ensemble& e, const RunPlan& plan);
void write_trajectories(const h5::Group& root, const std::vector<Trajectory>& trajectories);
// The rows a checkpoint holds, into trajectories configured alike, over a run of `steps` steps.
void read_trajectories(const h5::Group& root, std::vector<Trajectory>& trajectories,
                       long long steps);

}  // namespace qmaps
