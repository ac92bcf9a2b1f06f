// `qmaps discover CONFIG.toml --degree D --steps N`: the polynomial invariants of a map found from
// its orbits (core/invariant_discovery.hpp, docs/discover.md). The map and the orbits are the
// configuration's [map] and [ensemble], as `qmaps run` reads them; the first --orbits orbits run
// --steps steps on the scalar reference path, and every step gives a row m(x_{k+1}) − m(x_k) of
// the monomials of the map's state of degree 1 … D.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>
#include <vector>

#include "core/error.hpp"
#include "core/invariant_data.hpp"
#include "core/invariant_discovery.hpp"
#include "core/memory_limit.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/kinds/initial_conditions.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"
#include "ensembles/program/significant.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

// Monomials at most: the SVD's time grows as their cube (about 15 s for 1000 on one core, two
// minutes for 2000).
constexpr double max_monomials = 2000;

// The configuration's other tables are `qmaps run`'s and are not read here; a table or key that
// neither command knows is still an error.
void reject_unknown_except_run_tables(const Config& config) {
  for (const char* table : {"run", "output", "invariant_image", "chaos"})
    if (config.has_section(table)) config.keys(table);
  for (const char* array : {"histogram", "section", "trajectory"})
    for (std::size_t i = 0; i < config.entries(array); ++i)
      config.keys(std::string(array) + "[" + std::to_string(i) + "]");
  config.reject_unknown();
}

// The first `orbits` orbits of the configuration's ensemble, started as `qmaps run` starts them.
Ensemble first_orbits(const Model& model, const InitialConditions& ic, std::size_t orbits,
                      Start rule, double escape_bound) {
  if (!ic.generator().continues()) {
    std::vector<Phase> points(orbits);
    generate(ic.generator(), 0, points);
    return model.start(points, rule, escape_bound);
  }
  // An earlier run's final states: all are read, the first `orbits` kept as they are.
  Ensemble all = model.ensemble(ic.orbits());
  ic.start(model, all, rule, escape_bound, [](std::size_t, std::span<const Phase>) {});
  Ensemble e = model.ensemble(orbits);
  for (std::size_t k = 0; k < e.state.size(); ++k)
    std::copy_n(all.state[k].span().begin(), orbits, e.state[k].span().begin());
  for (std::size_t i = 0; i < orbits; ++i) {
    e.escape_step[i] = all.escape_step[i];
    e.escape_reason[i] = all.escape_reason[i];
  }
  e.fill_padding();
  return e;
}

// Orbits that all start on one level set J = c of an invariant J of the map (a shell of one
// energy, for the flow's H) stay on it, and every polynomial (J − c)·g then vanishes on the data:
// each would read as an invariant, as many as there are g. Refused, naming J, where J's values
// over the orbits agree within `level` (relative), the scale at which the null space is read.
void refuse_one_level_set(const Model& model, const Ensemble& e, double level) {
  const auto& names = model.invariant_names();
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<double> low(names.size(), inf), high(names.size(), -inf);
  std::size_t orbits = 0;
  for (std::size_t i = 0; i < e.orbits; ++i) {
    if (e.escape_step[i] >= 0) continue;
    const auto values = model.invariants(e, i);
    ++orbits;
    for (std::size_t k = 0; k < names.size(); ++k) {
      if (!std::isfinite(values[k])) continue;
      low[k] = std::min(low[k], values[k]);
      high[k] = std::max(high[k], values[k]);
    }
  }
  for (std::size_t k = 0; k < names.size(); ++k) {
    const double scale = std::max(std::fabs(low[k]), std::fabs(high[k]));
    if (!(low[k] <= high[k]) || !(high[k] - low[k] <= level * scale)) continue;
    throw usage_error(
        "the " + std::to_string(orbits) + " orbits lie on one level set of the map's invariant " +
        names[k] + " (" + names[k] + " = " + significant(low[k], 6) + " on every orbit, to " +
        significant(scale > 0 ? (high[k] - low[k]) / scale : 0.0) +
        " relative): every polynomial (" + names[k] + " - " + significant(low[k], 6) +
        ") g vanishes on the data and would read as an " + "invariant; give orbits spread over " +
        names[k] + "'s values (a box, or shells of " + "several energies)");
  }
}

// Coefficients left out below this times the largest: --drop, or the coefficients' uncertainty
// σ_{k+1}/σ_k (1/gap) where that is larger.
double drop_of(const Discovery& d, const DiscoverOptions& o) {
  return d.gap > 0 ? std::max(o.drop, 1 / d.gap) : o.drop;
}

void print_report(const Discovery& d, const DifferenceRows& rows,
                  const std::vector<std::string>& names, const DiscoverOptions& o,
                  std::ostream& out) {
  const std::size_t n = d.monomials;
  out << "rows:       " << d.rows << " steps, " << n << " monomials of degree 1 to " << o.degree
      << '\n';
  const std::size_t shown = std::min(n, std::max<std::size_t>(8, d.dimension + 2));
  out << "singular values sigma_i / sigma_1 (sigma_1 = " << significant(d.largest)
      << "), the smallest " << shown << ":\n";
  for (std::size_t i = n - shown; i < n; ++i) {
    char line[80];
    std::snprintf(line, sizeof line, "  sigma_%-5zu %.3e%s\n", i + 1, d.relative[i],
                  i + d.dimension == n ? "   <- null space from here" : "");
    out << line;
  }
  out << "null space: dimension " << d.dimension;
  if (o.threshold > 0)
    out << " (sigma_i / sigma_1 <= " << significant(o.threshold) << ")";
  else
    out << " (at the largest gap below " << significant(DiscoveryOptions{}.ceiling)
        << " sigma_1, if it is at least " << significant(DiscoveryOptions{}.minimum_gap) << ")";
  if (d.gap > 0)
    out << ", gap sigma_" << n - d.dimension << " / sigma_" << n - d.dimension + 1 << " = "
        << significant(d.gap);
  out << '\n';
  if (d.largest_gap_at > 0 && d.largest_gap_at != n - d.dimension)
    out << "largest gap: sigma_" << d.largest_gap_at << " / sigma_" << d.largest_gap_at + 1 << " = "
        << significant(d.largest_gap) << " (a null space of dimension " << n - d.largest_gap_at
        << " there)\n";
  if (d.invariants.empty()) return;
  out << "invariants: the reduced basis, largest coefficient 1, coefficients below "
      << significant(drop_of(d, o)) << " left out:\n";
  for (std::size_t k = 0; k < d.invariants.size(); ++k)
    out << "invariant " << k + 1 << ": "
        << rows.monomials().polynomial(d.invariants[k], names, drop_of(d, o)) << '\n';
}

void print_csv(const Discovery& d, const DifferenceRows& rows,
               const std::vector<std::string>& names, const DiscoverOptions& o,
               std::ostream& out) {
  out << "invariant,monomial,coefficient\n";
  for (std::size_t k = 0; k < d.invariants.size(); ++k) {
    const auto& c = d.invariants[k];
    for (std::size_t j = 0; j < c.size(); ++j) {
      if (!(std::fabs(c[j]) >= drop_of(d, o)) || c[j] == 0) continue;  // max |c| = 1
      out << k + 1 << ',' << rows.monomials().text(j, names) << ',' << significant(c[j], 17)
          << '\n';
    }
  }
}

}  // namespace

int discover_command(const DiscoverOptions& o, std::ostream& out) {
  if (o.degree < 1) throw usage_error("--degree must be >= 1 (got " + std::to_string(o.degree) + ")");
  if (o.steps < 1) throw usage_error("--steps must be >= 1 (got " + std::to_string(o.steps) + ")");
  if (o.orbits < 1) throw usage_error("--orbits must be >= 1 (got " + std::to_string(o.orbits) + ")");
  if (!(o.threshold >= 0 && o.threshold < 1))
    throw usage_error("--threshold must be in [0, 1) (0: at the largest gap; got " +
                      number_text(o.threshold) + ")");
  if (!(o.drop >= 0 && o.drop < 1))
    throw usage_error("--drop must be in [0, 1) (got " + number_text(o.drop) + ")");

  Config config = Config::load(o.config_path);
  for (const auto& s : o.sets) config.set(s);
  const auto model = map_of(config);
  const std::vector<std::string> names = discovery_variable_names(*model);

  // The size of the problem, before anything is allocated.
  const double monomials = Monomials::count(names.size(), o.degree);
  if (!(monomials <= max_monomials))
    throw usage_error("--degree " + std::to_string(o.degree) + ": " + significant(monomials, 6) +
                      " monomials of the " + std::to_string(names.size()) + " variables; at most " +
                      std::to_string(static_cast<long long>(max_monomials)) +
                      " (the SVD's time grows as their cube)");
  const double bytes = DifferenceRows::bytes(monomials);
  const MemoryLimit have = memory_limit();
  if (bytes > have.bytes)
    throw usage_error("--degree " + std::to_string(o.degree) + ": " + significant(monomials, 6) +
                      " monomials need about " + significant(bytes / (1 << 30)) + " GiB; " +
                      have.what + " is " + significant(have.bytes / (1 << 30)) + " GiB");

  const InitialConditions ic = InitialConditions::from_config(config, *model, stop_on_signal);
  Start rule = Start::taylor;
  try {
    rule = parse_start(config.string_or("ensemble", "start", "taylor"));
  } catch (const Error& e) {
    throw usage_error(config.where("ensemble", "start") + ": " + e.what());
  }
  const double escape_bound = config.number_or("run", "escape_bound", 1e8);
  if (!(escape_bound > 0)) throw usage_error(config.where("run", "escape_bound") + " must be > 0");
  reject_unknown_except_run_tables(config);

  const std::size_t orbits = std::min(static_cast<std::size_t>(o.orbits), ic.orbits());
  const double planned = static_cast<double>(orbits) * static_cast<double>(o.steps);
  if (planned < monomials)
    throw usage_error(
        "too few rows: " + std::to_string(orbits) + " orbits x " + std::to_string(o.steps) +
        " steps give " + significant(planned, 6) + " rows for " + significant(monomials, 6) +
        " monomials; give more --orbits or --steps (many more " + "rows than monomials)");

  Ensemble e = first_orbits(*model, ic, orbits, rule, escape_bound);
  refuse_one_level_set(*model, e, o.threshold > 0 ? o.threshold : DiscoveryOptions{}.ceiling);
  DifferenceRows rows(Monomials(names.size(), static_cast<int>(o.degree)));
  const StepsAdded added = add_steps(*model, e, o.steps, escape_bound, rows);
  if (rows.rows() < rows.monomials().size())
    throw usage_error(
        "too few rows: " + std::to_string(rows.rows()) + " steps of orbits that did not escape (" +
        std::to_string(added.escaped) + " of " + std::to_string(orbits) + " escaped" +
        (added.skipped ? "; " + std::to_string(added.skipped) +
                             " steps left out, their monomials beyond the largest double"
                       : std::string()) +
        ") for " + std::to_string(rows.monomials().size()) + " monomials");
  DiscoveryOptions options;
  options.threshold = o.threshold;
  const Discovery d = discover(rows, options);

  if (o.csv) {
    print_csv(d, rows, names, o, out);
    return 0;
  }
  out << "map:        " << model->name() << " (";
  for (std::size_t k = 0, shown = 0; k < model->param_specs().size(); ++k)
    if (!std::isnan(model->param_values()[k]))
      out << (shown++ ? ", " : "") << model->param_specs()[k].name << " = "
          << number_text(model->param_values()[k]);
  out << ")\n";
  out << "orbits:     " << orbits << " of " << ic.description() << "; " << o.steps << " steps, "
      << added.escaped << " escaped";
  if (added.skipped) out << ", " << added.skipped << " steps left out (a monomial overflowed)";
  out << '\n';
  out << "variables:  ";
  for (std::size_t k = 0; k < names.size(); ++k) out << (k ? ", " : "") << names[k];
  out << '\n';
  print_report(d, rows, names, o, out);
  return 0;
}

}  // namespace qmaps
