// `qmaps info FILE.h5`: what an earlier run holds — map, parameters, ensemble, orbits, steps,
// escapes by reason, each invariant's worst and median relative drift, its histograms and
// sections with their counts, and its chaos indicators' classes and quartiles; for a sweep, each
// point's summary.
#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "core/ensemble.hpp"
#include "core/error.hpp"
#include "ensembles/config/config.hpp"
#include "ensembles/config/map_config.hpp"
#include "ensembles/io/file_orbits.hpp"
#include "ensembles/io/h5.hpp"
#include "ensembles/io/output.hpp"
#include "ensembles/io/statistics.hpp"
#include "ensembles/program/commands.hpp"
#include "ensembles/program/run_setup.hpp"
#include "ensembles/program/significant.hpp"

namespace qmaps {
namespace {

// "128 x 128 bins over q1 x q2, 1000 samples (12 underflow, 3 overflow)"
std::string histogram_text(const h5::Group& h, const std::string& counts) {
  std::string text;
  const auto shape = h.shape(counts);
  for (std::size_t k = 0; k < shape.size(); ++k)
    text += (k ? " x " : "") + std::to_string(shape[k]);
  text += " bins over " + h.attr_string("x");
  if (h.has_attr("y")) text += " x " + h.attr_string("y");
  return text + ", " + std::to_string(h.attr_int64("samples")) + " samples (" +
         std::to_string(h.attr_int64("underflow")) + " underflow, " +
         std::to_string(h.attr_int64("overflow")) + " overflow)";
}

// Every histogram of the file below `g` (a group with counts and x_edges) outside the groups
// `shown` (those described above it): a run observer's that info knows no more of. Hard links
// only, at most 8 groups deep and 10^5 groups in all: a file whose links loop ends the search.
void other_histograms(const h5::Group& g, const std::string& path,
                      const std::vector<std::string>& shown, std::vector<std::string>& out,
                      std::size_t& groups_left, int depth = 0) {
  if (depth >= 8) return;
  for (const auto& name : g.members()) {
    const std::string at = path.empty() ? name : path + "/" + name;
    if (std::ranges::find(shown, at) != shown.end() || !g.has_group(name)) continue;
    if (groups_left == 0) return;
    --groups_left;
    const auto child = g.open_group(name);
    if (child.has("counts") && child.has("x_edges")) out.push_back(at);
    else other_histograms(child, at, shown, out, groups_left, depth + 1);
  }
}

// The points a section's group holds: its `orbit` column's length (a one-dimensional dataset).
std::size_t points_in(const h5::Group& s) {
  const auto shape = s.shape("orbit");
  if (shape.size() != 1)
    throw Error(ExitCode::io, "HDF5: dataset " + s.path() + "/orbit is not one-dimensional");
  return static_cast<std::size_t>(shape[0]);
}

// The per-orbit columns of the optional lane measurements the run took (each whose table its
// configuration has, core/observers/lane_observers.hpp), each as its least, median and largest
// value over the orbits never escaped.
void describe_measured(const h5::Group& root, std::size_t orbits,
                       const std::vector<std::uint8_t>& alive, std::ostream& out) {
  std::unique_ptr<Model> model;
  std::vector<std::string> measured;
  try {  // the file's configuration: one that cannot be read is the file's fault
    const Config config = Config::parse(root.attr_string("config_resolved"), "config_resolved");
    model = map_of(config, chaos_options_of(config));
    measured = measured_of(config, *model);
  } catch (const Error& e) {
    throw Error(ExitCode::io, "attribute config_resolved: " + std::string(e.what()));
  }
  if (measured.empty()) return;
  out << "measured:   per-orbit columns over the orbits never escaped\n";
  const auto always = model->lane_columns({}), taken = model->lane_columns(measured);
  for (std::size_t m = 0; m < taken.size(); ++m)
    for (std::size_t c = always[m].size(); c < taken[m].size(); ++c) {
      const std::string& path = taken[m][c].path;
      const auto [group, name] = dataset_at(root, path);
      const auto values = group.read_doubles(name, orbits);
      std::vector<double> kept;
      for (std::size_t i = 0; i < orbits; ++i)
        if (alive[i] && !std::isnan(values[i])) kept.push_back(values[i]);  // NaN: no tune
      if (kept.empty()) continue;
      const auto q = quantiles(std::move(kept), {0, 0.5, 1});
      out << "  " << path << ": least " << significant(q[0]) << ", median " << significant(q[1])
          << ", largest " << significant(q[2]) << '\n';
    }
}

// Each histogram of the group with its median and quartiles, a line each.
void quartile_lines(const h5::Group& histograms, std::ostream& out) {
  for (const auto& name : histograms.members()) {
    const auto h = histograms.open_group(name);
    out << "  " << name << std::string(name.size() < 14 ? 14 - name.size() : 1, ' ') << "median "
        << significant(h.attr_double("median")) << ", quartiles "
        << significant(h.attr_double("q1")) << " to " << significant(h.attr_double("q3")) << '\n';
  }
}

// A sweep's file: its axes, then one row per point with its summary (docs/sweeps.md).
int describe_sweep(const std::string& path, const h5::Group& root, std::ostream& out) {
  const auto sweep = root.open_group("sweep");
  const auto points = sweep.attr_int64("points");
  if (points < 1 || points > (1 << 24))
    throw Error(ExitCode::io, "attribute /sweep/points is " + std::to_string(points));
  const auto n = static_cast<std::size_t>(points);
  const auto shape = sweep.read_int64("shape", sweep.shape("shape").empty() ? 0 : sweep.shape("shape")[0]);
  std::vector<std::string> axes;
  std::vector<std::vector<double>> values;
  std::size_t product = 1;
  for (std::size_t k = 0; k < shape.size(); ++k) {
    axes.push_back(sweep.attr_string("axis" + std::to_string(k)));
    if (shape[k] < 1) throw Error(ExitCode::io, "/sweep/shape holds " + std::to_string(shape[k]));
    values.push_back(sweep.open_group("axes").read_doubles(axes.back(), static_cast<std::size_t>(shape[k])));
    product *= static_cast<std::size_t>(shape[k]);
  }
  if (shape.empty() || product != n)
    throw Error(ExitCode::io, "/sweep/shape does not multiply to its " + std::to_string(n) + " points");
  out << "file:       " << path << " (schema " << root.attr_int64("schema_version") << ")\n";
  out << "map:        " << root.attr_string("map") << ", sweep of " << n << " points over "
      << sweep.attr_string("axes") << ", " << root.attr_int64("steps") << " steps\n";
  const bool chaos = sweep.has("chaotic_fraction");
  const auto orbits = sweep.read_int64("orbits", n), escaped = sweep.read_int64("escaped", n);
  const auto drift = sweep.read_doubles("worst_drift", n);
  std::vector<double> fraction, megno;
  if (chaos) {
    fraction = sweep.read_doubles("chaotic_fraction", n);
    megno = sweep.read_doubles("median_megno", n);
  }
  const bool tunes = sweep.has("median_diffusion");
  std::vector<double> tune_fraction, diffusion;
  if (tunes) {
    tune_fraction = sweep.read_doubles("tunes_chaotic_fraction", n);
    diffusion = sweep.read_doubles("median_diffusion", n);
  }
  char line[256];
  out << "point";
  for (const auto& a : axes) {
    std::snprintf(line, sizeof line, " %16s", a.c_str());
    out << line;
  }
  out << "   orbits  escaped" << (chaos ? "  chaotic  median MEGNO" : "")
      << (tunes ? "  chaotic by diffusion  median diffusion" : "") << "  worst drift\n";
  for (std::size_t k = 0; k < n; ++k) {
    std::snprintf(line, sizeof line, "%5zu", k);
    out << line;
    std::size_t stride = n;
    for (std::size_t a = 0; a < axes.size(); ++a) {
      stride /= static_cast<std::size_t>(shape[a]);
      std::snprintf(line, sizeof line, " %16.6g", values[a][k / stride % values[a].size()]);
      out << line;
    }
    std::snprintf(line, sizeof line, " %8lld %8lld", static_cast<long long>(orbits[k]),
                  static_cast<long long>(escaped[k]));
    out << line;
    if (chaos) {
      std::snprintf(line, sizeof line, " %8.3g %13.3g", fraction[k], megno[k]);
      out << line;
    }
    if (tunes) {
      std::snprintf(line, sizeof line, " %21.3g %16.3g", tune_fraction[k], diffusion[k]);
      out << line;
    }
    std::snprintf(line, sizeof line, " %12.3g\n", drift[k]);
    out << line;
  }
  return 0;
}

int describe(const std::string& path, std::ostream& out) {
  const auto file = h5::File::open_read(path);
  const auto root = file.root();
  check_schema(root, path);
  if (root.has("sweep") && root.has_attr("schema_version") && root.has_attr("map") &&
      root.has_attr("steps"))
    return describe_sweep(path, root, out);
  for (const char* needed : {"schema_version", "map", "orbits", "steps"})
    if (!root.has_attr(needed))
      throw Error(ExitCode::io,
                  "'" + path + "' is not a qmaps output file (no attribute '" + needed + "')");
  out << "file:       " << path << " (schema " << root.attr_int64("schema_version") << ")\n";
  out << "map:        " << root.attr_string("map") << " (";
  bool first = true;
  for (const auto& name : root.attr_names())
    if (name.rfind("param.", 0) == 0) {
      out << (first ? "" : ", ") << name.substr(6) << " = " << number_text(root.attr_double(name));
      first = false;
    }
  out << ")\n";
  // A map written as formulas: each key's text (docs/formulas.md).
  std::vector<std::pair<std::string, std::string>> formulas;
  for (const auto& name : root.attr_names())
    if (name.rfind("formula.", 0) == 0) formulas.emplace_back(name.substr(8), root.attr_string(name));
  write_formulas(out, formulas);
  // The per-orbit columns read below: the escape reasons, each invariant's initial value and drift.
  const auto orbits = orbits_in(root, path, 8.0 * (1 + 2 * 8));
  out << "ensemble:   "
      << (root.has_attr("ensemble_description") ? root.attr_string("ensemble_description")
                                                : root.attr_string("ensemble"))
      << '\n';
  out << "orbits:     " << orbits << ", steps " << root.attr_int64("steps") << ", start "
      << root.attr_string("start");
  if (root.has_attr("rejected")) out << ", rejected " << root.attr_int64("rejected");
  out << '\n';

  // A run written with [output] per_orbit = false has no per-orbit datasets: its counts and
  // histograms only.
  const bool per_orbit = root.has("escape");
  std::vector<std::uint8_t> alive;
  std::map<std::int64_t, std::int64_t> by_reason;
  if (per_orbit) {
    const auto reasons = root.open_group("escape").read_int64("reason", orbits);
    alive.resize(reasons.size());
    for (std::size_t i = 0; i < reasons.size(); ++i) {
      alive[i] = reasons[i] == 0;
      if (reasons[i] != 0) ++by_reason[reasons[i]];
    }
  }
  out << "escaped:    " << root.attr_int64("escaped");
  for (const auto& [reason, count] : by_reason)
    out << (reason == by_reason.begin()->first ? " (" : ", ") << count << ' '
        << escape_reason_name(static_cast<EscapeReason>(reason));
  out << (by_reason.empty() ? "" : ")") << '\n';

  const auto invariants = root.open_group("invariants");
  out << "invariants: relative drift max|I_n - I_0|/|I_0| over the orbits never escaped"
      << (per_orbit ? "" : " (no per-orbit data: its histogram of log10)") << '\n';
  for (const auto& name : invariants.members()) {
    if (name == "image") continue;
    const auto inv = invariants.open_group(name);
    out << "  " << name << std::string(name.size() < 6 ? 6 - name.size() : 1, ' ');
    if (!per_orbit) {
      out << histogram_text(inv.open_group("drift_histogram"), "counts") << '\n';
      continue;
    }
    const auto initial = inv.read_doubles("initial", orbits),
               drift = inv.read_doubles("max_abs_drift", orbits);
    const DriftSummary s(initial, drift, alive);
    out << "worst " << significant(s.quantile(1)) << ", median " << significant(s.quantile(0.5));
    if (s.not_numbers())
      out << " (" << s.not_numbers() << " of " << s.orbits() << " orbits' " << name
          << " is not a number: no drift can be measured)";
    out << '\n';
  }
  if (per_orbit && root.has_attr("config_resolved")) describe_measured(root, orbits, alive, out);
  if (invariants.has("image"))
    out << "invariant image: " << histogram_text(invariants.open_group("image"), "counts") << '\n';
  if (root.has("histograms")) {
    out << "histograms:\n";
    const auto histograms = root.open_group("histograms");
    for (const auto& name : histograms.members())
      out << "  " << name << ": " << histogram_text(histograms.open_group(name), "counts") << '\n';
  }
  if (root.has("sections")) {
    out << "sections:\n";
    const auto sections = root.open_group("sections");
    for (const auto& name : sections.members()) {
      const auto s = sections.open_group(name);
      out << "  " << name << ": " << s.attr_string("plane") << " = "
          << number_text(s.attr_double("value")) << " (" << s.attr_string("direction") << ", "
          << s.attr_string("mode") << "), " << s.attr_int64("crossings") << " crossings"
          << (s.has_attr("interpolated")
                  ? " (" + std::to_string(s.attr_int64("interpolated")) + " interpolated)"
                  : std::string())
          << ", "
          << points_in(s) << " points kept (cap " << s.attr_int64("cap") << "); "
          << histogram_text(s, "density") << '\n';
    }
  }
  if (root.has("chaos")) {
    const auto chaos = root.open_group("chaos");
    const auto regular = chaos.attr_int64("regular"), chaotic = chaos.attr_int64("chaotic");
    out << "chaos:      " << chaotic << " chaotic, " << regular
        << " regular (MEGNO above / not above " << number_text(chaos.attr_double("megno_threshold"))
        << "), " << chaos.attr_int64("escaped") << " escaped; chaotic fraction "
        << significant(chaos.attr_double("chaotic_fraction")) << '\n';
    quartile_lines(chaos.open_group("histograms"), out);
  }
  if (root.has("tunes")) {
    const auto tunes = root.open_group("tunes");
    out << "tunes:      windows of " << tunes.attr_int64("window") << " steps, Hann order "
        << tunes.attr_int64("order") << "; " << tunes.attr_int64("chaotic") << " chaotic, "
        << tunes.attr_int64("regular") << " regular (diffusion above / not above "
        << number_text(tunes.attr_double("diffusion_threshold")) << "), "
        << tunes.attr_int64("escaped") << " escaped, " << tunes.attr_int64("no_tune")
        << " without a tune, " << tunes.attr_int64("round_off")
        << " at round-off; chaotic fraction " << significant(tunes.attr_double("chaotic_fraction"))
        << '\n';
    quartile_lines(tunes.open_group("histograms"), out);
    out << "  frequency map: " << histogram_text(tunes.open_group("frequency_map"), "counts") << '\n';
  }
  std::vector<std::string> others;
  std::size_t groups_left = 100000;
  other_histograms(root, "",
                   {"initial", "final", "escape", "invariants", "histograms", "sections", "chaos",
                    "tunes", "trajectories"},
                   others, groups_left);
  if (!others.empty()) out << "other histograms:\n";
  for (const auto& path : others) {
    const auto h = root.open_group(path);
    out << "  " << path << ": " << histogram_text(h, "counts");
    if (h.has_attr("median"))
      out << "; median " << significant(h.attr_double("median")) << ", quartiles "
          << significant(h.attr_double("q1")) << " to " << significant(h.attr_double("q3"));
    out << '\n';
  }
  return 0;
}

}  // namespace

// Any failure to read the file names it.
int info_command(const std::string& path, std::ostream& out) {
  try {
    return describe(path, out);
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.find("'" + path + "'") != std::string::npos) throw;
    throw Error(e.code(), "'" + path + "': " + what);
  }
}

}  // namespace qmaps
