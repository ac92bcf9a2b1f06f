#include "core/invariant_data.hpp"

#include <algorithm>

#include "core/execution.hpp"
#include "core/run_plan.hpp"

namespace qmaps {

std::vector<std::size_t> discovery_variables(const Model& model) {
  std::vector<std::size_t> out;
  const auto inert = model.inert_state();
  for (std::size_t k = 0; k < model.state_names().size(); ++k)
    if (std::find(inert.begin(), inert.end(), k) == inert.end()) out.push_back(k);
  return out;
}

std::vector<std::string> discovery_variable_names(const Model& model) {
  std::vector<std::string> out;
  for (std::size_t k : discovery_variables(model)) {
    std::string name(model.state_names()[k]);
    if (const auto at = name.find('_'); at != std::string::npos)
      name = name.substr(0, at) + '[' + name.substr(at + 1) + ']';
    out.push_back(name);
  }
  return out;
}

StepsAdded add_steps(const Model& model, Ensemble& e, long long steps, double escape_bound,
                     DifferenceRows& rows) {
  const std::vector<std::size_t> variables = discovery_variables(model);
  const std::size_t n = variables.size(), orbits = e.orbits;
  std::vector<double> before(orbits * n), x(n), y(n);
  const auto take = [&](std::vector<double>& into) {
    for (std::size_t i = 0; i < orbits; ++i)
      for (std::size_t k = 0; k < n; ++k) into[i * n + k] = e.state[variables[k]][i];
  };
  StepsAdded added;
  RunPlan plan;
  plan.total = steps;
  plan.escape_bound = escape_bound;
  plan.measure_orbits = false;
  for (long long step = 0; step < steps; ++step) {
    take(before);
    plan.first = step;
    plan.last = step + 1;
    model.advance(e, plan, Execution{});
    for (std::size_t i = 0; i < orbits; ++i) {
      if (e.escape_step[i] >= 0) continue;
      for (std::size_t k = 0; k < n; ++k) {
        x[k] = before[i * n + k];
        y[k] = e.state[variables[k]][i];
      }
      if (rows.add(x, y))
        ++added.rows;
      else
        ++added.skipped;
    }
  }
  added.escaped = e.escaped();
  return added;
}

}  // namespace qmaps
