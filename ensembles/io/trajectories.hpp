#pragma once
// The trajectories' rows (core/observers/trajectory/trajectory.hpp): recorded when the run
// starts, by stepping copies of those orbits on the scalar reference path, which every path
// reproduces bit for bit. Written, kept and merged as ensembles/io/run_observers describes them.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/ensemble.hpp"
#include "core/model.hpp"
#include "core/observers/trajectory/trajectory.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

// The column names every trajectory of this model has, and orbit i's row of them at e's step
// (`continuous` is continuous_model(model), null when there is none): `qmaps orbit` prints the
// same rows.
std::vector<std::string> trajectory_columns(const Model& model);
std::vector<double> trajectory_row(const Model& model, const Model* continuous, const Ensemble& e,
                                   std::size_t i);
// Keeps, of each trajectory's orbits, those in [first, first + count), numbered from `first` (a
// shard's): a trajectory may be left with none.
void keep_orbits_in(std::vector<Trajectory>& trajectories, std::size_t first, std::size_t count);
// Puts t's rows in the order `order` (row order[r] becomes row r).
void reorder_rows(Trajectory& t, std::span<const std::size_t> order);
// Fills t's rows from the started ensemble e (at step 0), over plan.total steps.
void record(Trajectory& t, const Model& model, const Ensemble& e, const RunPlan& plan);

}  // namespace qmaps
