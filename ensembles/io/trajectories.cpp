#include "ensembles/io/trajectories.hpp"

#include <array>

#include "core/execution.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {

std::vector<std::string> trajectory_columns(const Model& model) {
  std::vector<std::string> out = {"t", "q1", "q2", "p1", "p2"};
  for (const auto& name : model.invariant_names()) out.push_back(name);
  if (const auto continuous = continuous_model(model))
    for (const auto& name : continuous->invariant_names()) out.push_back(name + "_cont");
  for (const auto& name : model.indicator_names()) out.push_back(name);
  return out;
}

std::vector<double> trajectory_row(const Model& model, const Model* continuous, const Ensemble& e,
                                   std::size_t i) {
  const Phase x = model.phase(e, i);
  const std::vector<double> invariants = model.invariants(e, i);
  const std::vector<double> integrals =
      continuous ? continuous->invariants_of(std::array{x.q1, x.q2, x.p1, x.p2})
                 : std::vector<double>{};
  const std::vector<double> indicators = model.indicators(e, i);
  std::vector<double> row;  // allocated once: qmaps orbit makes a row per step
  row.reserve(5 + invariants.size() + integrals.size() + indicators.size());
  row.insert(row.end(), {model.time(e, i), x.q1, x.q2, x.p1, x.p2});
  row.insert(row.end(), invariants.begin(), invariants.end());
  row.insert(row.end(), integrals.begin(), integrals.end());
  row.insert(row.end(), indicators.begin(), indicators.end());
  return row;
}

void record(Trajectory& t, const Model& model, const Ensemble& e, const RunPlan& plan) {
  const auto continuous = continuous_model(model);
  t.columns = trajectory_columns(model);
  t.orbit.clear();
  t.step.clear();
  t.values.assign(t.columns.size(), {});
  if (t.orbits.empty()) return;  // a shard's trajectory of orbits all in other shards
  // Copies of the orbits, advanced together on the scalar reference path.
  Ensemble copy = model.ensemble(t.orbits.size());
  for (std::size_t j = 0; j < t.orbits.size(); ++j) copy.set_orbit(j, e, t.orbits[j]);
  copy.fill_padding();
  copy.step = e.step;
  // Rows by step first; reordered orbit by orbit at the end.
  std::vector<std::vector<std::size_t>> rows_of(t.orbits.size());
  RunPlan segment = plan;
  segment.measure_orbits = false;
  for (long long n = e.step;;) {
    for (std::size_t j = 0; j < t.orbits.size(); ++j) {
      if (copy.escape_step[j] >= 0) continue;  // rows stop before the escape
      rows_of[j].push_back(t.orbit.size());
      t.orbit.push_back(static_cast<std::int64_t>(t.orbits[j]));
      t.step.push_back(n);
      const std::vector<double> row = trajectory_row(model, continuous.get(), copy, j);
      for (std::size_t k = 0; k < row.size(); ++k) t.values[k].push_back(row[k]);
    }
    if (n >= plan.total) break;
    segment.first = n;
    segment.last = std::min(plan.total, n + t.every);
    model.advance(copy, segment, Execution{});
    n = segment.last;
  }
  // Orbit by orbit, each in step order.
  std::vector<std::size_t> order;
  for (const auto& rows : rows_of) order.insert(order.end(), rows.begin(), rows.end());
  reorder_rows(t, order);
}

void reorder_rows(Trajectory& t, std::span<const std::size_t> order) {
  const auto reorder = [&](auto& column) {
    auto sorted = column;
    for (std::size_t r = 0; r < order.size(); ++r) sorted[r] = column[order[r]];
    column = std::move(sorted);
  };
  reorder(t.orbit);
  reorder(t.step);
  for (auto& column : t.values) reorder(column);
}

void keep_orbits_in(std::vector<Trajectory>& trajectories, std::size_t first, std::size_t count) {
  for (Trajectory& t : trajectories) {
    std::vector<std::size_t> kept;
    for (const std::size_t o : t.orbits)
      if (o >= first && o < first + count) kept.push_back(o - first);
    t.orbits = std::move(kept);
  }
}

}  // namespace qmaps
