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

#include "core/error.hpp"
#include "core/isa.hpp"
#include "ensembles/io/ranks.hpp"
#include "core/version.hpp"
#include "ensembles/io/measured_output.hpp"
#include "ensembles/io/run_observers/run_observers.hpp"

namespace qmaps {
namespace {

struct Column {
  const h5::Group& group;
  std::string name;
};

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

}  // namespace

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
  root.attr("kernel_flags", std::string(kernel_flags()));
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
  // part on this thread, between its writes, which are mostly the kernel's copies. The run
  // observers' output (drift histograms: a log10 per orbit and invariant, the most computing) is
  // described meanwhile on a thread of its own. OpenMP threads would spin idle between the
  // parts on the cores they need.
  auto described = on_a_thread_if_possible([&run] { return describe_run(run); });

  write_build(root);
  root.attr("map", std::string(model.name()));
  const auto specs = model.param_specs();
  const auto values = model.param_values();
  for (std::size_t k = 0; k < specs.size(); ++k)
    root.attr("param." + std::string(specs[k].name), values[k]);
  for (const auto& [key, text] : model.formulas()) root.attr("formula." + key, text);
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
  write_output(root, described.get(), rows, run.per_orbit);

  if (!run.per_orbit) return;
  const auto escape = root.create_group("escape");
  write_rows<std::int64_t>(escape, "step", e.escape_step.span().first(n), rows);
  write_rows<std::uint8_t>(escape, "reason", e.escape_reason.span().first(n), rows);
  std::string codes;
  for (int k = 0; k <= static_cast<int>(last_escape_reason); ++k)
    codes += (k ? ", " : "") + std::to_string(k) + " " +
             std::string(escape_reason_name(static_cast<EscapeReason>(k)));
  escape.attr("reason_codes", codes);
}

}  // namespace qmaps
