#include <cmath>
#include <cstdio>
#include <optional>
#include <ostream>
#include <sstream>

#include "core/error.hpp"
#include "core/observers/lane_observers.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/io/trajectories.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/interrupt.hpp"
#include "kernels/catalogue.hpp"

namespace qmaps {
namespace {

constexpr long long orbit_chunk = 1 << 16;  // steps between two looks for a signal

Phase parse_ic(const std::string& text) {
  std::istringstream in(text);
  double x[4];
  std::string item;
  int k = 0;
  while (std::getline(in, item, ',')) {
    const auto v = number_in(item);
    if (k == 4 || !v || !std::isfinite(*v))
      throw usage_error("--ic expects four finite numbers q1,q2,p1,p2, got '" + text + "'");
    x[k++] = *v;
  }
  if (k != 4) throw usage_error("--ic expects four numbers q1,q2,p1,p2, got '" + text + "'");
  return {x[0], x[1], x[2], x[3]};
}

struct OrbitStart {
  std::unique_ptr<Model> model;
  Phase ic;
  Start start;
};

// The orbit's model and initial condition, every option checked.
OrbitStart orbit_start(const OrbitOptions& o) {
  // With --chaos the map advances its chaos record with the state (core/tangent_map.hpp): the
  // same steps, bit for bit, and the indicators of the orbit so far on every row.
  auto model = map_named(o.map, parse_params(o.sets),
                         o.chaos ? std::optional(ChaosOptions{true, 10}) : std::nullopt);
  Phase ic = parse_ic(o.ic);
  if (o.energy) {  // p2 from H_cont = E, with the sign --ic gives it
    const auto continuous = model->continuous();
    if (!continuous)
      throw usage_error("--energy: map '" + std::string(model->name()) +
                        "' names no continuous Hamiltonian to measure the energy by (a formula "
                        "map's [map] continuous)");
    const double rest = continuous->energy({ic.q1, ic.q2, ic.p1, 0.0});
    const double p2_squared = 2 * (*o.energy - rest);
    if (!std::isfinite(*o.energy))
      throw usage_error("--energy " + number_text(*o.energy) + ": the energy must be finite");
    if (!(p2_squared >= 0))
      throw usage_error("--energy " + number_text(*o.energy) + ": below the energy " +
                        number_text(rest) + " of (q1, q2, p1) = (" + number_text(ic.q1) + ", " +
                        number_text(ic.q2) + ", " + number_text(ic.p1) +
                        ") with p2 = 0; no p2 reaches it");
    ic.p2 = std::copysign(std::sqrt(p2_squared), ic.p2);
  }
  if (o.steps < 0) throw usage_error("--steps must be >= 0");
  if (o.every < 1) throw usage_error("--every must be >= 1");
  if (!(o.escape_bound > 0)) throw usage_error("--escape-bound must be > 0");
  if (o.tunes != 0 && (o.tunes < 32 || o.tunes > (1 << 20) || (o.tunes & (o.tunes - 1)) != 0))
    throw usage_error("--tunes " + std::to_string(o.tunes) +
                      ": the window must be a power of two from 32 to 1048576");
  if (2 * o.tunes > o.steps)
    throw usage_error("--tunes " + std::to_string(o.tunes) + ": its two windows need " +
                      std::to_string(2 * o.tunes) + " steps; --steps gives " +
                      std::to_string(o.steps));
  return {std::move(model), ic, parse_start(o.start)};
}

}  // namespace

std::string orbit_tunes(const OrbitOptions& o) {
  const auto [model, ic, start] = orbit_start(o);
  if (o.tunes == 0) return "";
  Ensemble e = model->ensemble(1, std::vector<std::string>{std::string(TuneColumns::key)});
  model->start_at(e, 0, std::span<const Phase>(&ic, 1), start, o.escape_bound);
  e.fill_padding();
  RunPlan plan;
  plan.total = plan.last = 2 * o.tunes;  // in one call: the windows are analysed whole
  plan.escape_bound = o.escape_bound;
  plan.tunes = {o.tunes, 2};
  model->advance(e, plan, Execution{});
  const auto tunes = e.columns_of(lane_index<Tunes>);
  char text[512];
  std::snprintf(text, sizeof text,
                "tunes (NAFF of q1, q2, Hann order 2, folded to [0, 1/2]) over steps 1 to %lld: "
                "nu1 = %.17g, nu2 = %.17g; over steps %lld to %lld: nu1 = %.17g, nu2 = %.17g; "
                "diffusion log10|dnu| = %.6g%s",
                o.tunes, tunes[TuneColumns::nu1][0], tunes[TuneColumns::nu2][0], o.tunes + 1,
                2 * o.tunes, tunes[TuneColumns::nu1_second][0], tunes[TuneColumns::nu2_second][0],
                tunes[TuneColumns::diffusion][0],
                tunes[TuneColumns::diffusion][0] == diffusion_floor() ? " (round-off: no change)"
                : e.escape_step[0] >= 0 ? " (escaped within the windows: NaN)"
                                        : "");
  return text;
}

std::string orbit_rows(const OrbitOptions& o, const OrbitColumns& columns_of,
                       const OrbitRow& row) {
  const auto [model, ic, start] = orbit_start(o);
  Ensemble e = model->start(std::span<const Phase>(&ic, 1), start, o.escape_bound);
  // The continuous system's H and its case's second integral at the phase point: the flow's
  // invariants (kernels/flow.hpp) for the map's potential, so that the map's oscillating energy
  // error shows beside its own exact invariants.
  // At n = 0 the exponents and ⟨Y⟩ are not yet defined (0/0: NaN).
  const auto continuous = continuous_model(*model);
  // n, then the trajectory row (docs/hdf5-schema.md), without t where the map's physical time
  // is n h.
  const std::size_t from = model->time_per_orbit() ? 0 : 1;
  std::vector<std::string> columns = trajectory_columns(*model);
  columns.erase(columns.begin(), columns.begin() + static_cast<std::ptrdiff_t>(from));
  columns.insert(columns.begin(), "n");
  columns_of(columns);
  RunPlan plan;
  plan.total = o.steps;
  plan.escape_bound = o.escape_bound;
  plan.measure_orbits = false;
  for (long long n = 0;;) {
    if (e.escape_step[0] >= 0)
      return "the orbit escaped at step " + std::to_string(e.escape_step[0]) + " (" +
             std::string(escape_reason_name(static_cast<EscapeReason>(e.escape_reason[0]))) +
             "); rows stop before it";
    std::vector<double> values = trajectory_row(*model, continuous.get(), e, 0);
    // n in place of t where t is n h, else before it.
    if (from > 0) values[0] = static_cast<double>(e.step);
    else values.insert(values.begin(), static_cast<double>(e.step));
    row(values);
    if (n >= o.steps) break;
    // In chunks (exact: a segmented advance equals one call), so that a signal under an
    // InterruptGuard (the Python module's call) stops a long orbit at once.
    const long long next = std::min(o.steps, n + o.every);
    for (; n < next; n = plan.last) {
      stop_if_interrupted(("stepping the orbit at step " + std::to_string(n) + " of " +
                           std::to_string(o.steps)).c_str(),
                          "stopped, no rows returned");
      plan.first = n;
      plan.last = std::min(next, n + orbit_chunk);
      model->advance(e, plan, Execution{});
    }
  }
  return "";
}

int orbit_command(const OrbitOptions& o, std::ostream& out, std::ostream& log) {
  char buf[64];
  const std::string escaped = orbit_rows(
      o,
      [&](const std::vector<std::string>& columns) {
        for (std::size_t k = 0; k < columns.size(); ++k) out << (k ? "," : "") << columns[k];
        out << '\n';
      },
      [&](std::span<const double> values) {
        out << static_cast<long long>(values[0]);
        for (std::size_t k = 1; k < values.size(); ++k) {
          std::snprintf(buf, sizeof buf, ",%.17g", values[k]);
          out << buf;
        }
        out << '\n';
      });
  if (!escaped.empty()) log << "qmaps orbit: " << escaped << '\n';
  if (o.tunes > 0) log << "qmaps orbit: " << orbit_tunes(o) << '\n';
  return 0;
}

}  // namespace qmaps
