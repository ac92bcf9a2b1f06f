#include "ensembles/io/sweep_output.hpp"
#include "core/observers/invariants/invariant_columns.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/observers/tunes/tunes.hpp"
#include "ensembles/io/run_observers/chaos_summary.hpp"
#include "ensembles/io/run_observers/tune_summary.hpp"
#include "ensembles/io/statistics.hpp"

namespace qmaps {
namespace {

// Point k's group name: its index, zero-padded so that the names sort as the points.
std::string run_name(std::size_t k, std::size_t points) {
  const std::string digits = std::to_string(points - 1), index = std::to_string(k);
  return std::string(digits.size() - index.size(), '0') + index;
}

// The largest relative drift max|I_n − I_0|/|I_0| (absolute where I_0 = 0) of any invariant over
// the orbits that never escaped; NaN when every orbit escaped, or when an orbit's invariant is not
// a number (never a number below the drift that cannot be measured).
double worst_drift(const Model& model, const Ensemble& e) {
  std::vector<std::uint8_t> bounded(e.orbits);
  for (std::size_t i = 0; i < e.orbits; ++i) bounded[i] = e.escape_step[i] < 0;
  double worst = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t k = 0; k < model.invariant_names().size(); ++k) {
    const DriftSummary drift(invariant_initial(e, k).span().first(e.orbits),
                             invariant_drift(e, k).span().first(e.orbits), bounded);
    if (drift.not_numbers()) return std::numeric_limits<double>::quiet_NaN();
    const double d = drift.quantile(1);
    if (!std::isnan(d)) worst = std::isnan(worst) ? d : std::max(worst, d);
  }
  return worst;
}

}  // namespace

std::vector<h5::Group> create_sweep_runs(const h5::Group& root, std::size_t points) {
  const auto runs = root.create_group("sweep").create_group("runs");
  std::vector<h5::Group> out;
  for (std::size_t k = 0; k < points; ++k) out.push_back(runs.create_group(run_name(k, points)));
  return out;
}

void write_sweep(const h5::Group& root, const Sweep& sweep, std::span<const RunRecord> runs) {
  const std::size_t points = sweep.points();
  const RunRecord& first = runs.front();
  write_build(root);
  root.attr("map", std::string(first.model.name()));
  for (const auto& [key, text] : first.model.formulas()) root.attr("formula." + key, text);
  root.attr("steps", static_cast<std::int64_t>(first.plan.total));
  root.attr("isa", std::string(isa_name(first.execution.isa)));
  root.attr("threads", static_cast<std::int64_t>(first.execution.threads));
  root.attr("chains", static_cast<std::int64_t>(first.execution.chains));
  root.attr("config", first.config_text);
  root.attr("command_line", first.command_line);
  root.attr("started", first.started);
  root.attr("finished", first.finished);

  const auto g = root.open_group("sweep");
  g.attr("points", static_cast<std::int64_t>(points));
  std::string axes;
  for (const auto& axis : sweep.axes()) axes += (axes.empty() ? "" : ", ") + axis.parameter;
  g.attr("axes", axes);
  g.attr("order", std::string("row-major: point k is the axes' values at the digits of k, "
                              "the first axis slowest"));

  std::vector<std::int64_t> shape;
  for (const auto n : sweep.shape()) shape.push_back(static_cast<std::int64_t>(n));
  g.write("shape", std::span<const std::int64_t>(shape));
  const auto axes_group = g.create_group("axes");
  for (std::size_t k = 0; k < sweep.axes().size(); ++k) {
    const auto& axis = sweep.axes()[k];
    axes_group.write(axis.name(), std::span<const double>(axis.values));
    g.attr("axis" + std::to_string(k), axis.name());
  }

  const auto specs = first.model.param_specs();
  const auto parameters = g.create_group("parameters");
  for (std::size_t j = 0; j < specs.size(); ++j) {
    std::vector<double> column(points);
    for (std::size_t k = 0; k < points; ++k) column[k] = runs[k].model.param_values()[j];
    parameters.write(std::string(specs[j].name), std::span<const double>(column));
  }

  std::vector<std::int64_t> orbits(points), escaped(points), regular(points), chaotic(points);
  std::vector<double> fraction(points), megno(points), lyapunov(points), drift(points);
  const bool chaos = !first.model.indicator_names().empty();
  const bool tunes = first.plan.tunes.window > 0;
  std::vector<std::int64_t> tune_regular(points), tune_chaotic(points);
  std::vector<double> tune_fraction(points), diffusion(points);
  for (std::size_t k = 0; k < points; ++k) {
    if (!tunes) break;
    const TuneTable t = tune_table(runs[k].ensemble, runs[k].tunes.diffusion_threshold);
    tune_regular[k] = t.regular;
    tune_chaotic[k] = t.chaotic;
    tune_fraction[k] = t.chaotic_fraction();
    diffusion[k] = quantile(t.finite(TuneColumns::diffusion), 0.5);
  }
  for (std::size_t k = 0; k < points; ++k) {
    const RunRecord& run = runs[k];
    orbits[k] = static_cast<std::int64_t>(run.ensemble.orbits);
    escaped[k] = static_cast<std::int64_t>(run.ensemble.escaped());
    drift[k] = worst_drift(run.model, run.ensemble);
    if (!chaos) continue;
    const ChaosTable t = chaos_table(run.model, run.ensemble, run.chaos.megno_threshold);
    regular[k] = t.regular;
    chaotic[k] = t.chaotic;
    fraction[k] = t.chaotic_fraction();
    lyapunov[k] = quantile(t.bounded(0), 0.5);  // indicator_names(): lyapunov, fli, megno, …
    megno[k] = quantile(t.bounded(2), 0.5);
  }
  g.write("orbits", std::span<const std::int64_t>(orbits));
  g.write("escaped", std::span<const std::int64_t>(escaped));
  g.write("worst_drift", std::span<const double>(drift));
  if (chaos) {
    g.attr("megno_threshold", first.chaos.megno_threshold);
    g.write("regular", std::span<const std::int64_t>(regular));
    g.write("chaotic", std::span<const std::int64_t>(chaotic));
    g.write("chaotic_fraction", std::span<const double>(fraction));
    g.write("median_megno", std::span<const double>(megno));
    g.write("median_lyapunov", std::span<const double>(lyapunov));
  }

  if (tunes) {
    g.attr("diffusion_threshold", first.tunes.diffusion_threshold);
    g.write("tunes_regular", std::span<const std::int64_t>(tune_regular));
    g.write("tunes_chaotic", std::span<const std::int64_t>(tune_chaotic));
    g.write("tunes_chaotic_fraction", std::span<const double>(tune_fraction));
    g.write("median_diffusion", std::span<const double>(diffusion));
  }

  const auto point_runs = g.open_group("runs");
  for (std::size_t k = 0; k < points; ++k)
    write_run(point_runs.open_group(run_name(k, points)), runs[k]);
}

}  // namespace qmaps
