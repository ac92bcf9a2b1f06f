#include "ensembles/io/output.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <cstdint>
#include <future>
#include <stdexcept>
#include <system_error>
#include <vector>

#include <unistd.h>
#include <omp.h>

#include "core/error.hpp"
#include "ensembles/io/ranks.hpp"
#include "core/version.hpp"
#include "ensembles/io/statistics.hpp"
#include "core/observers/invariants/invariant_columns.hpp"

namespace qmaps {
namespace {

struct Column {
  const h5::Group& group;
  std::string name;
};

// row(i) for every i in [0, count), on `threads` threads; each row computed alone.
template <class Row>
void for_each_row(std::size_t count, int threads, Row row) {
  const long long rows = static_cast<long long>(count);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long long r = 0; r < rows; ++r) row(static_cast<std::size_t>(r));
}

// The first row and the count of part p of `count` rows (empty past them).
std::pair<std::size_t, std::size_t> part_of(std::size_t p, std::size_t count) {
  const std::size_t first = std::min(p * orbits_per_part, count);
  return {first, std::min(orbits_per_part, count - first)};
}

// Datasets of rows.total elements of T (doubles unless said), computed orbits_per_part rows at a
// time: fill(first, count, values) sets values[k][0, count) of column k for this process's rows
// [first, first + count), written at rows.first + first.
template <class T = double, class Fill>
void write_columns(const std::vector<Column>& columns, Rows rows, Fill fill) {
  for (const auto& c : columns) c.group.create_column<T>(c.name, rows.total);
  std::vector<std::vector<T>> values(columns.size(),
                                     std::vector<T>(std::min(rows.count, orbits_per_part)));
  for (std::size_t p = 0, parts = parts_of(rows.count); p < parts; ++p) {
    const auto [first, count] = part_of(p, rows.count);
    if (count > 0) fill(first, count, values);
    for (std::size_t k = 0; k < columns.size(); ++k)
      columns[k].group.write_part<T>(columns[k].name, rows.first + first,
                                     std::span<const T>(values[k]).first(count));
  }
}

// Every lane measurement's per-orbit columns, each at its path.
void write_measured_columns(const h5::Group& root, const Ensemble& e, Rows rows) {
  for (std::size_t c = 0; c < e.columns.size(); ++c) {
    const auto [group, name] = dataset_at(root, e.column_specs[c].path, true);
    write_rows<double>(group, name, e.columns[c].span().first(e.orbits), rows);
  }
}

// counts (shape bins, or bins × bins), edges per axis, and the attributes of a histogram.
void write_histogram(const h5::Group& g, const Histogram& h, const std::string& counts_name) {
  std::vector<hsize_t> dims;
  for (const Axis& a : h.axes()) dims.push_back(static_cast<hsize_t>(a.bins));
  g.write(counts_name, std::span<const std::int64_t>(h.counts()), dims);
  const char* edge_names[2] = {"x_edges", "y_edges"};
  const char* coordinate_names[2] = {"x", "y"};
  for (std::size_t k = 0; k < h.axes().size(); ++k) {
    g.write(edge_names[k], h.axes()[k].edges());
    g.attr(coordinate_names[k], h.axes()[k].coordinate);
  }
  g.attr("underflow", h.underflow());
  g.attr("overflow", h.overflow());
  g.attr("samples", h.samples());
}

// A histogram as every rank's counts add up to.
void write_histogram_over_ranks(const h5::Group& g, Histogram h, const std::string& counts_name) {
  add_over_ranks(h);
  write_histogram(g, h, counts_name);
}

void write_observers(const h5::Group& root, const Observers& o, long long stride, Rows orbits) {
  if (!o.densities.empty()) {
    const auto histograms = root.create_group("histograms");
    for (const auto& d : o.densities) {
      const auto g = histograms.create_group(d.histogram.name());
      write_histogram_over_ranks(g, d.histogram, "counts");
      g.attr("stride", static_cast<std::int64_t>(stride));
    }
  }
  if (o.sections.empty()) return;
  const auto sections = root.create_group("sections");
  for (const auto& s : o.sections) {
    const auto g = sections.create_group(s.name);
    // The points' columns in parts, read from the slots in (orbit, step) order: no second copy.
    // A rank's points follow those of the ranks before it, as its orbits do.
    const SectionPoints& points = *s.points;
    const std::size_t n = points.size();
    const auto mine = static_cast<std::int64_t>(n);
    const Rows rows{static_cast<std::size_t>(ranks::before(mine)), n,
                    static_cast<std::size_t>(ranks::sum(mine))};
    std::vector<SectionPoint> part(std::min(n, orbits_per_part));
    SectionPoints::Cursor cursor;
    write_columns<std::int64_t>({{g, "orbit"}, {g, "step"}}, rows,
                                [&](std::size_t first, std::size_t count, auto& values) {
                                  points.read(first, std::span(part).first(count), cursor);
                                  for (std::size_t i = 0; i < count; ++i) {
                                    values[0][i] = part[i].orbit + static_cast<std::int64_t>(orbits.first);
                                    values[1][i] = part[i].step;
                                  }
                                });
    write_columns({{g, "x"}, {g, "y"}}, rows,
                  [&](std::size_t first, std::size_t count, auto& values) {
                    points.read(first, std::span(part).first(count), cursor);
                    for (std::size_t i = 0; i < count; ++i) {
                      values[0][i] = part[i].x;
                      values[1][i] = part[i].y;
                    }
                  });
    Histogram density = s.density;
    add_over_ranks(density);
    write_histogram(g, density, "density");
    g.attr("plane", std::string(coordinate_name(s.plane)));
    g.attr("value", s.value);
    g.attr("direction", std::string(s.direction > 0 ? "+" : s.direction < 0 ? "-" : "both"));
    g.attr("mode", std::string(section_mode_names[static_cast<std::size_t>(s.mode)]));
    if (s.mode == SectionMode::exact) g.attr("interpolated", ranks::sum(s.interpolated));
    g.attr("cap", s.cap);
    g.attr("crossings", density.samples());
  }
}

// /chaos (docs/chaos.md): each indicator of every orbit; each one's histogram and quartiles over
// the orbits that stayed bounded (log10 of the GALIs); the orbits' classes by MEGNO.
void write_chaos(const h5::Group& root, const RunRecord& run, Rows rows) {
  if (run.model.indicator_names().empty()) return;
  ChaosTable t = chaos_table(run.model, run.ensemble, run.chaos.megno_threshold);
  t.regular = ranks::sum(t.regular);
  t.chaotic = ranks::sum(t.chaotic);
  t.escaped = ranks::sum(t.escaped);
  const auto chaos = root.create_group("chaos");
  chaos.attr("megno_threshold", run.chaos.megno_threshold);
  chaos.attr("regular", t.regular);
  chaos.attr("chaotic", t.chaotic);
  chaos.attr("escaped", t.escaped);
  chaos.attr("chaotic_fraction", t.chaotic_fraction());
  chaos.attr("class_codes", std::string("0 regular, 1 chaotic (megno > megno_threshold), 2 escaped"));
  chaos.attr("unit", std::string("Lyapunov exponents per step"));
  if (run.per_orbit) {
    for (std::size_t k = 0; k < t.names.size(); ++k)
      write_rows<double>(chaos, t.names[k], t.values[k], rows);
    write_rows<std::uint8_t>(chaos, "class", t.classes, rows);
  }
  const auto histograms = chaos.create_group("histograms");
  for (std::size_t k = 0; k < t.names.size(); ++k) {
    // Every rank's values, in orbit order: the same quartiles and range on every rank.
    const std::vector<double> bounded = ranks::gathered(t.bounded(k));
    double lo = 0, hi = 1;
    if (!bounded.empty()) {
      const auto [min, max] = std::minmax_element(bounded.begin(), bounded.end());
      lo = *min;
      hi = *max > *min ? std::nextafter(*max, HUGE_VAL) : *min + 1;
    }
    const std::string name = t.histogram_name(k);
    Histogram h(name, {Axis{name, lo, hi, run.chaos.bins}});
    for (double v : bounded) h.add(&v);
    const auto g = histograms.create_group(name);
    write_histogram(g, h, "counts");
    g.attr("q1", quantile(bounded, 0.25));
    g.attr("median", quantile(bounded, 0.5));
    g.attr("q3", quantile(bounded, 0.75));
  }
}

}  // namespace

ChaosTable chaos_table(const Model& model, const Ensemble& e, double megno_threshold) {
  ChaosTable t;
  t.names = model.indicator_names();
  const std::size_t n = e.orbits;
  t.values.assign(t.names.size(), std::vector<double>(n));
  for_each_row(n, omp_get_max_threads(), [&](std::size_t i) {
    const auto v = model.indicators(e, i);
    for (std::size_t k = 0; k < v.size(); ++k) t.values[k][i] = v[k];
  });
  t.classes.resize(n);
  if (t.names.empty()) return t;
  const std::size_t megno = 2;  // indicator_names(): lyapunov, fli, megno, …
  for (std::size_t i = 0; i < n; ++i) {
    t.classes[i] = e.escape_step[i] >= 0                        ? 2
                   : t.values[megno][i] > megno_threshold ? 1
                                                          : 0;
    ++(t.classes[i] == 0 ? t.regular : t.classes[i] == 1 ? t.chaotic : t.escaped);
  }
  return t;
}

double ChaosTable::chaotic_fraction() const {
  return regular + chaotic > 0 ? static_cast<double>(chaotic) / static_cast<double>(regular + chaotic)
                               : std::nan("");
}

bool ChaosTable::logarithmic(std::size_t k) const { return names[k].starts_with("gali"); }

std::string ChaosTable::histogram_name(std::size_t k) const {
  return logarithmic(k) ? "log10_" + names[k] : names[k];
}

std::vector<double> ChaosTable::bounded(std::size_t k) const {
  std::vector<double> out;
  for (std::size_t i = 0; i < classes.size(); ++i) {
    const double v = logarithmic(k) ? std::log10(values[k][i]) : values[k][i];
    if (classes[i] != 2 && std::isfinite(v)) out.push_back(v);
  }
  return out;
}

DriftHistogram drift_histogram(const Ensemble& e, std::size_t k) {
  DriftHistogram d{Histogram("log10_relative_drift", {{"log10_relative_drift", -18.0, 0.0, 72}})};
  for (std::size_t i = 0; i < e.orbits; ++i) {
    const double drift = invariant_drift(e, k)[i];
    if (drift == 0) {
      ++d.zero;
      continue;
    }
    const double x = std::log10(relative_drift(invariant_initial(e, k)[i], drift));
    d.histogram.add(&x);
  }
  return d;
}

DatasetAt dataset_at(const h5::Group& root, const std::string& path, bool make) {
  const std::size_t slash = path.rfind('/');
  if (slash == std::string::npos) throw std::logic_error("dataset_at: " + path + " is in no group");
  const std::string parent = path.substr(0, slash);
  return {make ? root.group_at(parent) : root.open_group(parent), path.substr(slash + 1)};
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

std::string session_line(long long first, long long last, const Execution& x,
                         const std::string& started, const std::string& finished,
                         const std::string& command_line) {
  const int n = ranks::count();
  return "steps " + std::to_string(first) + "-" + std::to_string(last) + ", " +
         std::string(isa_name(x.isa)) + ", " +
         (n > 1 ? std::to_string(n) + " ranks x " : std::string()) + std::to_string(x.threads) +
         " thread" + (x.threads == 1 ? "" : "s") + (n > 1 ? " each" : "") + ", " + started +
         " to " + finished + ": " + command_line + "\n";
}

void create_phase(const h5::Group& g, std::size_t n) {
  for (const auto name : phase_names) g.create_column<double>(std::string(name), n);
}

void write_phase_part(const h5::Group& g, std::size_t first, std::span<const Phase> points) {
  std::vector<double> column(points.size());
  for (int k = 0; k < 4; ++k) {
    for (std::size_t i = 0; i < points.size(); ++i) column[i] = points[i].*phase_members[k];
    g.write_part<double>(std::string(phase_names[k]), first, column);
  }
}

void read_phase_part(const h5::Group& g, std::size_t first, std::size_t total,
                     std::span<Phase> points) {
  std::vector<double> column(points.size());
  for (int k = 0; k < 4; ++k) {
    const std::string name(phase_names[k]);
    if (g.shape(name) != std::vector<hsize_t>{total})
      throw Error(ExitCode::io, "HDF5: dataset " + g.path() + "/" + name + " does not hold " +
                                    std::to_string(total) + " elements");
    g.read_part<double>(name, first, column);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (!std::isfinite(column[i]))
        throw Error(ExitCode::io, "HDF5: " + g.path() + "/" + name + " of orbit " +
                                      std::to_string(first + i) + " is not finite");
      points[i].*phase_members[k] = column[i];
    }
  }
}

std::size_t parts_of(std::size_t count) {
  return static_cast<std::size_t>(
      ranks::max(static_cast<std::int64_t>((count + orbits_per_part - 1) / orbits_per_part)));
}

void add_over_ranks(Histogram& h) {
  std::vector<std::int64_t> cells(h.counts().begin(), h.counts().end());
  cells.push_back(h.underflow());
  cells.push_back(h.overflow());
  ranks::sum(cells);
  const std::int64_t over = cells.back();
  cells.pop_back();
  const std::int64_t under = cells.back();
  cells.pop_back();
  h.restore(cells, under, over);
}

template <class T>
void write_rows(const h5::Group& g, const std::string& name, std::span<const T> values, Rows rows) {
  g.create_column<T>(name, rows.total);
  for (std::size_t p = 0, parts = parts_of(rows.count); p < parts; ++p) {
    const auto [first, count] = part_of(p, rows.count);
    g.write_part<T>(name, rows.first + first, values.subspan(first, count));
  }
}
template void write_rows<double>(const h5::Group&, const std::string&, std::span<const double>, Rows);
template void write_rows<std::int64_t>(const h5::Group&, const std::string&,
                                       std::span<const std::int64_t>, Rows);
template void write_rows<std::uint8_t>(const h5::Group&, const std::string&,
                                       std::span<const std::uint8_t>, Rows);

void copy_phase(const h5::Group& from, const h5::Group& to, Rows rows) {
  create_phase(to, rows.total);
  std::vector<Phase> part(std::min(rows.count, orbits_per_part));
  for (std::size_t p = 0, parts = parts_of(rows.count); p < parts; ++p) {
    const auto [first, count] = part_of(p, rows.count);
    const auto points = std::span<Phase>(part).first(count);
    read_phase_part(from, rows.first + first, rows.total, points);
    write_phase_part(to, rows.first + first, points);
  }
}

void check_schema(const h5::Group& root, const std::string& path) {
  if (!root.has_attr("schema_version"))
    throw Error(ExitCode::io, "'" + path + "' is not a qmaps output file (no schema_version)");
  const auto schema = root.attr_int64("schema_version");
  if (schema != schema_version)
    throw Error(ExitCode::io, "'" + path + "' has schema " + std::to_string(schema) +
                                  (schema > schema_version ? ", newer than" : ", not") +
                                  " the schema " + std::to_string(schema_version) + " qmaps " +
                                  build::version + " reads" +
                                  (root.has_attr("qmaps_version")
                                       ? " (written by qmaps " + root.attr_string("qmaps_version") + ")"
                                       : std::string()));
}

void write_build(const h5::Group& root) {
  root.attr("schema_version", schema_version);
  root.attr("qmaps_version", build::version);
  root.attr("git_commit", build::commit);
  root.attr("compiler", build::compiler);
  root.attr("compiler_flags", build::engine_flags);
  root.attr("kernel_flags", build::kernel_flags);
}

namespace {

// f on a thread of its own; where none can be made (ulimit -u, or -v short of its stack), on the
// calling thread when its result is asked for: the same result, and no run lost at its end.
template <class F>
auto on_a_thread_if_possible(F f) {
  try {
    return std::async(std::launch::async, f);
  } catch (const std::system_error&) {
    return std::async(std::launch::deferred, f);
  }
}

}  // namespace

void write_run(const h5::Group& root, const RunRecord& run) {
  const Model& model = run.model;
  const Ensemble& e = run.ensemble;
  const std::size_t n = e.orbits;
  const Rows rows = run.rows.or_all(n);
  // The columns computed for the file (final phase points and invariants) are computed part by
  // part on this thread, between its writes, which are mostly the kernel's copies. The drift
  // histograms (a log10 per orbit and invariant, the most computing) are counted meanwhile, each
  // by a thread of its own. OpenMP threads would spin idle between the parts on the cores they
  // need.
  std::vector<std::future<DriftHistogram>> drifts;
  for (std::size_t k = 0; k < model.invariant_names().size(); ++k)
    drifts.push_back(on_a_thread_if_possible([&e, k] { return drift_histogram(e, k); }));

  write_build(root);
  root.attr("map", std::string(model.name()));
  const auto specs = model.param_specs();
  const auto values = model.param_values();
  for (std::size_t k = 0; k < specs.size(); ++k)
    root.attr("param." + std::string(specs[k].name), values[k]);
  root.attr("steps", static_cast<std::int64_t>(run.plan.total));
  if (!model.time_per_orbit()) root.attr("time", model.time(e, 0));
  root.attr("orbits", static_cast<std::int64_t>(rows.total));
  root.attr("ensemble", run.ensemble_kind);
  root.attr("ensemble_description", run.ensemble_description);
  root.attr("rejected", ranks::sum(static_cast<std::int64_t>(run.rejected)));
  root.attr("seed", static_cast<std::int64_t>(run.seed));
  root.attr("start", std::string(start_name(run.start)));
  root.attr("stride", static_cast<std::int64_t>(run.plan.stride));
  root.attr("escape_bound", run.plan.escape_bound);
  root.attr("escaped", ranks::sum(static_cast<std::int64_t>(e.escaped())));
  root.attr("per_orbit", static_cast<std::int64_t>(run.per_orbit));
  root.attr("isa", std::string(isa_name(run.execution.isa)));
  root.attr("threads", static_cast<std::int64_t>(run.execution.threads));
  root.attr("chains", static_cast<std::int64_t>(run.execution.chains));
  root.attr("ranks", static_cast<std::int64_t>(ranks::count()));
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  std::string hosts;
  for (const auto& h : ranks::gathered(std::string(host))) hosts += h + "\n";
  root.attr("hosts", hosts);
  root.attr("config", run.config_text);
  root.attr("config_resolved", run.config_resolved);
  root.attr("command_line", run.command_line);
  root.attr("started", run.started);
  root.attr("finished", run.finished);
  root.attr("sessions", run.sessions);
  if (!run.shard.empty()) {
    root.attr("shard", run.shard);
    root.attr("shard_first", run.shard_first);
    root.attr("orbits_total", run.orbits_total);
  }

  const auto& inv_names = model.invariant_names();
  if (run.per_orbit) {
    const auto final_group = root.create_group("final");
    write_columns({{final_group, "q1"}, {final_group, "q2"}, {final_group, "p1"},
                   {final_group, "p2"}, {final_group, "t"}},
                  rows, [&](std::size_t first, std::size_t count, auto& values) {
                    for (std::size_t i = 0; i < count; ++i) {
                      const Phase p = model.phase(e, first + i);
                      for (int k = 0; k < 4; ++k) values[k][i] = p.*phase_members[k];
                      values[4][i] = model.time(e, first + i);
                    }
                  });
    const auto state = final_group.create_group("state");
    state.attr("step", static_cast<std::int64_t>(e.step));
    const auto names = model.state_names();
    for (std::size_t k = 0; k < names.size(); ++k)
      write_rows<double>(state, std::string(names[k]), e.state[k].span().first(n), rows);
  }

  const auto invariants = root.create_group("invariants");
  std::vector<h5::Group> groups;
  for (const auto& name : inv_names) groups.push_back(invariants.create_group(name));
  if (run.per_orbit) {
    std::vector<Column> finals;
    for (std::size_t k = 0; k < inv_names.size(); ++k) finals.push_back({groups[k], "final"});
    // On the run's own path, lanes at a time.
    write_columns(finals, rows, [&](std::size_t first, std::size_t count, auto& values) {
      std::vector<double*> out;
      for (auto& v : values) out.push_back(v.data());
      model.invariants_of_orbits(e, first, count, run.execution.isa, out);
    });
    write_measured_columns(root, e, rows);
  }
  for (std::size_t k = 0; k < inv_names.size(); ++k) {
    DriftHistogram drift = drifts[k].get();
    add_over_ranks(drift.histogram);
    const auto dg = groups[k].create_group("drift_histogram");
    write_histogram(dg, drift.histogram, "counts");
    dg.attr("zero", ranks::sum(drift.zero));
  }
  if (run.image) {
    Histogram image = run.image->histogram;
    std::size_t ix = 0, iy = 0;
    for (std::size_t k = 0; k < inv_names.size(); ++k) {
      if (inv_names[k] == image.axes()[0].coordinate) ix = k;
      if (inv_names[k] == image.axes()[1].coordinate) iy = k;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const double v[2] = {invariant_initial(e, ix)[i], invariant_initial(e, iy)[i]};
      image.add(v);
    }
    write_histogram_over_ranks(invariants.create_group("image"), image, "counts");
  }
  if (run.observers) write_observers(root, *run.observers, run.plan.stride, rows);
  write_chaos(root, run, rows);
  if (run.trajectories) write_trajectories(root, *run.trajectories);

  if (!run.per_orbit) return;
  const auto escape = root.create_group("escape");
  write_rows<std::int64_t>(escape, "step", e.escape_step.span().first(n), rows);
  write_rows<std::uint8_t>(escape, "reason", e.escape_reason.span().first(n), rows);
  std::string codes;
  for (int k = 0; k <= static_cast<int>(EscapeReason::wrong_branch); ++k)
    codes += (k ? ", " : "") + std::to_string(k) + " " +
             std::string(escape_reason_name(static_cast<EscapeReason>(k)));
  escape.attr("reason_codes", codes);
}

}  // namespace qmaps
