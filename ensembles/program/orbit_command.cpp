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
  const auto model = make_model(o.map, parse_params(o.sets));
  const Phase ic = parse_ic(o.ic);
  if (o.steps < 0) throw usage_error("--steps must be >= 0");
  if (o.every < 1) throw usage_error("--every must be >= 1");
  if (!(o.escape_bound > 0)) throw usage_error("--escape-bound must be > 0");
  const Start start = parse_start(o.start);

  Ensemble e = model->start(std::span<const Phase>(&ic, 1), start, o.escape_bound);
  out << (model->time_per_orbit() ? "n,t,q1,q2,p1,p2" : "n,q1,q2,p1,p2");
  for (const auto& name : model->invariant_names()) out << ',' << name;
  if (o.chaos) out << ",lyapunov,fli,megno";
  out << '\n';
  // The chaos indicators follow the orbit's own state with the tangent map (the same values,
  // bit for bit, as the rows' steps); at n = 0 they are not yet defined (NaN for λ and ⟨Y⟩).
  std::vector<double> state(model->state_names().size()), deviation(state.size());
  for (std::size_t k = 0; k < state.size(); ++k) {
    state[k] = e.state[k][0];
    deviation[k] = k < 4 ? 0.5 : 0.0;  // initial_deviation()
  }
  ChaosSums<double> sums;
  const auto chaos_columns = [&] {
    if (!o.chaos) return std::vector<double>{};
    if (sums.steps == 0) return std::vector<double>{std::nan(""), 0.0, std::nan("")};
    return std::vector<double>{sums.lyapunov(), sums.fli, sums.megno()};
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
    row(out, *model, e, chaos_columns());
    if (n >= o.steps) break;
    plan.first = n;
    plan.last = std::min(o.steps, n + o.every);
    model->advance(e, plan, Execution{});
    if (o.chaos) model->advance_with_tangent(state, deviation, sums, plan.last - n);
    n = plan.last;
  }
  return 0;
}

}  // namespace qmaps
