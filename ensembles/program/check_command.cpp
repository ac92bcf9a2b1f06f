// `qmaps check --map NAME` (or a formula map's FILE.toml): invariant drift and reversibility over a
// random box, not a test of integrability. A random box of orbits runs `steps` steps; for each
// invariant the map has at its parameters, percentiles of the orbits' max relative drift; then
// reversibility: the ensemble is reversed, runs the same steps back and is reversed again, and the
// largest difference of its phase points from the start is the reversibility error.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "core/error.hpp"
#include "core/observers/invariants/invariant_columns.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/io/statistics.hpp"
#include "ensembles/kinds/box.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/significant.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

constexpr long long max_check_orbits = 10000000;  // 10^7: about 2 GB of check's arrays

// Parameters a check uses where the user gives none: the map's example (its MapFacts;
// docs/maps.md §2). The example's optional parameters (case2-hky's weights) fill in only when
// none of them is given.
ParamValues with_check_defaults(const MapEntry& map, ParamValues given) {
  const ParamValues example = param_values(map.facts->example);
  bool optional_given = false;
  for (const auto& p : map.params) optional_given |= p.optional && given.count(p.name);
  for (const auto& p : map.params) {
    if (given.count(p.name) || !(p.required() || (p.optional && !optional_given))) continue;
    if (const auto it = example.find(p.name); it != example.end())
      given[std::string(p.name)] = it->second;
  }
  return given;
}

const MapEntry& entry_of(const std::string& name) {
  for (const auto& m : catalogue())
    if (m.name == name) return m;
  make_model(name, {});  // throws the unknown-map error
  throw usage_error("unknown map '" + name + "'");
}

}  // namespace

int check_command(const CheckOptions& o, std::ostream& out) {
  if (o.orbits <= 0) throw usage_error("--orbits must be > 0");
  if (o.orbits > max_check_orbits)
    throw usage_error("--orbits must be at most " + std::to_string(max_check_orbits) + " (got " +
                      std::to_string(o.orbits) + "): check is a quick report; qmaps run takes more");
  if (!(o.escape_bound > 0) || !std::isfinite(o.escape_bound))
    throw usage_error("--escape-bound must be a finite number > 0 (got " +
                      number_text(o.escape_bound) + ")");
  if (o.steps <= 0) throw usage_error("--steps must be > 0");
  if (o.seed < 0) throw usage_error("--seed must be >= 0");
  if (!(o.box > 0)) throw usage_error("--box must be > 0");
  // a built-in map at its example's parameters where none is given, or a formula map's file
  const auto model = o.map.ends_with(".toml")
                         ? map_named(o.map, parse_params(o.sets), std::nullopt)
                         : entry_of(o.map).make(with_check_defaults(entry_of(o.map),
                                                                    parse_params(o.sets)));

  const double q = o.box;
  const Box box({{{-q, q}, {-q, q}, {-q, q}, {-q, q}}}, static_cast<std::uint64_t>(o.seed),
                static_cast<std::size_t>(o.orbits));
  const auto points = generate(box).points;
  Ensemble e = model->start(points, Start::taylor, o.escape_bound);
  std::vector<Phase> initial(e.orbits);  // at node 0, as phase() computes it
  for (std::size_t i = 0; i < e.orbits; ++i) initial[i] = model->phase(e, i);
  Execution x;
  x.isa = resolve_isa("auto");
  x.threads = omp_get_max_threads();
  RunPlan plan;
  plan.total = plan.last = o.steps;
  plan.escape_bound = o.escape_bound;
  model->advance(e, plan, x);

  out << "map " << model->name() << " (";
  for (std::size_t k = 0; k < model->param_specs().size(); ++k)
    if (!std::isnan(model->param_values()[k]))
      out << (k ? ", " : "") << model->param_specs()[k].name << " = "
          << number_text(model->param_values()[k]);
  out << "): " << o.orbits << " orbits uniform in [-" << number_text(q) << ", " << number_text(q)
      << "]^4 (seed " << o.seed << "), " << o.steps << " steps, " << e.escaped() << " escaped\n";
  const auto& names = model->invariant_names();
  out << "invariants checked:";
  for (std::size_t k = 0; k < names.size(); ++k) out << (k ? ", " : " ") << names[k];
  out << (names.empty() ? " none" : "")
      << " (those the map has at these parameters; whether it is integrable is qmaps "
         "integrability's question)\n";

  std::vector<std::uint8_t> alive(e.orbits);
  for (std::size_t i = 0; i < e.orbits; ++i) alive[i] = e.escape_step[i] < 0;
  out << "relative drift max|I_n - I_0|/|I_0| over the orbits never escaped:\n";
  out << "  invariant     median        90%        99%      worst\n";
  for (std::size_t k = 0; k < names.size(); ++k) {
    const DriftSummary s(invariant_initial(e, k).span().first(e.orbits),
                         invariant_drift(e, k).span().first(e.orbits), alive);
    char line[160];
    std::snprintf(line, sizeof line, "  %-9s %10s %10s %10s %10s\n", names[k].c_str(),
                  significant(s.quantile(0.5)).c_str(), significant(s.quantile(0.9)).c_str(),
                  significant(s.quantile(0.99)).c_str(), significant(s.quantile(1)).c_str());
    out << line;
  }

  // Reversibility: reverse, the same steps back, reverse again; compare phase points.
  model->reverse(e);
  plan.measure_orbits = false;
  model->advance(e, plan, x);
  model->reverse(e);
  double worst = 0;
  std::size_t compared = 0;
  for (std::size_t i = 0; i < e.orbits; ++i) {
    if (e.escape_step[i] >= 0) continue;
    const Phase a = model->phase(e, i), b = initial[i];
    worst = std::max({worst, std::fabs(a.q1 - b.q1), std::fabs(a.q2 - b.q2), std::fabs(a.p1 - b.p1),
                      std::fabs(a.p2 - b.p2)});
    ++compared;
  }
  out << "reversibility: " << o.steps << " steps forward, reversed, " << o.steps
      << " back: max |(q, p) - (q0, p0)| = " << significant(worst) << " over " << compared
      << " orbits\n";
  return 0;
}

}  // namespace qmaps
