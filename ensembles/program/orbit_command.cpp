#include <cmath>
#include <cstdio>
#include <optional>
#include <ostream>
#include <sstream>

#include "core/error.hpp"
#include "kernels/catalogue.hpp"
#include "ensembles/program/commands.hpp"

namespace qmaps {
namespace {

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

// One CSV row: n, then t for a map whose physical time is per orbit, q, p, the invariants, and
// any further columns.
void row(std::ostream& out, const Model& model, const Ensemble& e,
         const std::vector<double>& more) {
  std::vector<double> values;
  if (model.time_per_orbit()) values.push_back(model.time(e, 0));
  const Phase x = model.phase(e, 0);
  values.insert(values.end(), {x.q1, x.q2, x.p1, x.p2});
  for (double v : model.invariants(e, 0)) values.push_back(v);
  values.insert(values.end(), more.begin(), more.end());
  char buf[64];
  out << e.step;
  for (double v : values) {
    std::snprintf(buf, sizeof buf, ",%.17g", v);
    out << buf;
  }
  out << '\n';
}

}  // namespace

int orbit_command(const OrbitOptions& o, std::ostream& out, std::ostream& log) {
  // With --chaos the map advances its chaos record with the state (core/tangent_map.hpp): the
  // same steps, bit for bit, and the indicators of the orbit so far on every row.
  const auto model = o.chaos ? make_model(o.map, parse_params(o.sets), ChaosOptions{true, 10})
                             : make_model(o.map, parse_params(o.sets));
  Phase ic = parse_ic(o.ic);
  if (o.energy) {  // p2 from H_cont = E, with the sign --ic gives it
    const double rest = model->continuous().energy({ic.q1, ic.q2, ic.p1, 0.0});
    const double p2_squared = 2 * (*o.energy - rest);
    if (!std::isfinite(*o.energy) || !(p2_squared >= 0))
      throw usage_error("--energy " + number_text(*o.energy) + ": below the energy " +
                        number_text(rest) + " of (q1, q2, p1) = (" + number_text(ic.q1) + ", " +
                        number_text(ic.q2) + ", " + number_text(ic.p1) +
                        ") with p2 = 0; no p2 reaches it");
    ic.p2 = std::copysign(std::sqrt(p2_squared), ic.p2);
  }
  if (o.steps < 0) throw usage_error("--steps must be >= 0");
  if (o.every < 1) throw usage_error("--every must be >= 1");
  if (!(o.escape_bound > 0)) throw usage_error("--escape-bound must be > 0");
  const Start start = parse_start(o.start);

  Ensemble e = model->start(std::span<const Phase>(&ic, 1), start, o.escape_bound);
  // The continuous system's H and its case's second integral at the phase point: the flow's
  // invariants (kernels/flow.hpp) for the map's potential, so that the map's oscillating energy
  // error shows beside its own exact invariants.
  const auto continuous = continuous_model(*model);
  out << (model->time_per_orbit() ? "n,t,q1,q2,p1,p2" : "n,q1,q2,p1,p2");
  for (const auto& name : model->invariant_names()) out << ',' << name;
  for (const auto& name : continuous->invariant_names()) out << ',' << name << "_cont";
  for (const auto& name : model->indicator_names()) out << ',' << name;
  out << '\n';
  // At n = 0 the exponents and ⟨Y⟩ are not yet defined (0/0: NaN).
  const auto more_columns = [&] {
    const Phase x = model->phase(e, 0);
    std::vector<double> values = continuous->invariants_of(std::array{x.q1, x.q2, x.p1, x.p2});
    for (double v : model->indicators(e, 0)) values.push_back(v);
    return values;
  };
  RunPlan plan;
  plan.total = o.steps;
  plan.escape_bound = o.escape_bound;
  plan.track_invariants = false;
  for (long long n = 0;;) {
    if (e.escape_step[0] >= 0) {
      log << "qmaps orbit: the orbit escaped at step " << e.escape_step[0] << " ("
          << escape_reason_name(static_cast<EscapeReason>(e.escape_reason[0]))
          << "); rows stop before it\n";
      return 0;
    }
    row(out, *model, e, more_columns());
    if (n >= o.steps) break;
    plan.first = n;
    plan.last = std::min(o.steps, n + o.every);
    model->advance(e, plan, Execution{});
    n = plan.last;
  }
  return 0;
}

}  // namespace qmaps
