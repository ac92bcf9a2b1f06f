#include "ensembles/io/checkpoint.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/error.hpp"
#include "core/escape.hpp"
#include "ensembles/io/ranks.hpp"
#include "core/version.hpp"

namespace qmaps {
namespace {

Error corrupt(const std::string& path, const std::string& what) {
  return Error(ExitCode::io, "'" + path + "' is not a checkpoint qmaps can resume: " + what);
}

// Reads elements [first, first + out.size()) of dataset `name` of `g`, which must hold exactly
// `total` elements, into `out`.
template <class T>
void read_column(const h5::Group& g, const std::string& name, std::span<T> out, std::size_t first,
                 std::size_t total) {
  if (g.shape(name) != std::vector<hsize_t>{total})
    throw Error(ExitCode::io, "HDF5: dataset " + g.path() + "/" + name + " does not hold " +
                                  std::to_string(total) + " elements");
  g.read_part<T>(name, first, out);
}
template <class T>
void read_column(const h5::Group& g, const std::string& name, std::span<T> out, Rows rows) {
  read_column(g, name, out, rows.first, rows.total);
}
template <class T>
std::vector<T> read_column(const h5::Group& g, const std::string& name, std::size_t first,
                           std::size_t count, std::size_t total) {
  std::vector<T> out(count);
  read_column(g, name, std::span<T>(out), first, total);
  return out;
}

Error bad(const h5::Group& g, const std::string& what) {
  return Error(ExitCode::io, "HDF5: " + g.path() + ": " + what);
}

// Counts of a histogram as a run leaves them: 0 ≤ count ≤ 2^53 (no sum of them can overflow).
void restore_histogram(const h5::Group& g, const std::string& counts, Histogram& h) {
  const auto cells = g.read_int64(counts, h.counts().size());
  const std::int64_t under = g.attr_int64("underflow"), over = g.attr_int64("overflow");
  constexpr std::int64_t most = std::int64_t{1} << 53;
  for (const std::int64_t c : cells)
    if (c < 0 || c > most) throw bad(g, counts + " holds the count " + std::to_string(c));
  if (under < 0 || under > most || over < 0 || over > most)
    throw bad(g, "underflow or overflow out of range");
  h.restore(cells, under, over);
}

}  // namespace

void write_checkpoint(const std::string& path, RunRecord record, const h5::Group* initial) {
  h5::AtomicFile out(path);
  auto file = out.create_hdf5();
  const auto root = file.root();
  record.per_orbit = true;
  write_run(root, record);
  root.attr("checkpoint_version", checkpoint_version);
  const std::size_t n = record.ensemble.orbits;
  const Rows rows = record.rows.or_all(n);
  if (initial) copy_phase(*initial, root.create_group("initial"), rows);
  if (record.observers) write_kept(root, *record.observers, rows);
  file.close();
  out.commit();
}

void write_kept(const h5::Group& root, const Observers& observers, Rows rows) {
  for (const auto& s : observers.sections) {
    const auto kept = s.points->kept();
    write_rows<std::int64_t>(root.open_group("sections").open_group(s.name), "kept", kept,
                             rows.or_all(kept.size()));
  }
}

h5::File open_checkpoint(const std::string& path) {
  h5::File file = h5::File::open_read(path);
  const auto root = file.root();
  if (!root.has_attr("checkpoint_version"))
    throw corrupt(path, "it has no attribute checkpoint_version (a run's final file is no checkpoint)");
  std::int64_t version = 0, schema = -1;
  std::string writer = "?";
  try {  // an attribute of another type or shape is named
    version = root.attr_int64("checkpoint_version");
    if (root.has_attr("schema_version")) schema = root.attr_int64("schema_version");
    if (root.has_attr("qmaps_version")) writer = root.attr_string("qmaps_version");
  } catch (const Error& e) {
    throw corrupt(path, e.what());
  }
  if (version != checkpoint_version || schema != schema_version)
    throw corrupt(path, "it has checkpoint version " + std::to_string(version) + " and schema " +
                            std::to_string(schema) + " (written by qmaps " + writer + "); qmaps " +
                            build::version + " resumes checkpoint version " +
                            std::to_string(checkpoint_version) + ", schema " +
                            std::to_string(schema_version));
  return file;
}

void read_ensemble(const h5::Group& root, const Model& model, Ensemble& e, Rows rows,
                   std::size_t first) {
  if (rows.count == 0) rows = {0, e.orbits, e.orbits};
  const std::size_t n = rows.count;
  if (first + n > e.orbits || rows.first + n > rows.total)
    throw std::logic_error("read_ensemble: orbits beyond the ensemble");
  const auto state = root.open_group("final").open_group("state");
  const auto names = model.state_names();
  for (std::size_t k = 0; k < names.size(); ++k)
    read_column(state, std::string(names[k]), e.state[k].span().subspan(first, n), rows);
  e.step = state.attr_int64("step");
  const auto escape = root.open_group("escape");
  read_column(escape, "step", e.escape_step.span().subspan(first, n), rows);
  read_column(escape, "reason", e.escape_reason.span().subspan(first, n), rows);
  for (std::size_t c = 0; c < e.columns.size(); ++c) {
    const auto [group, name] = dataset_at(root, e.column_specs[c].path);
    read_column(group, name, e.columns[c].span().subspan(first, n), rows);
  }
  // What a run leaves: escapes at steps 0 … step (or −1) with a known reason, and for the orbits
  // that have not escaped, finite states and measured columns, none below its least value.
  if (e.step < 0) throw bad(state, "step " + std::to_string(e.step));
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t i = first + j;
    const std::int64_t at = e.escape_step[i];
    if (at < -1 || at > e.step)
      throw bad(escape, "orbit " + std::to_string(j) + " escaped at step " + std::to_string(at));
    if (at < 0 && e.escape_reason[i] != 0)
      throw bad(escape, "orbit " + std::to_string(j) + " has not escaped but has escape reason " +
                            std::to_string(e.escape_reason[i]));
    if (at >= 0 && (e.escape_reason[i] == 0 || e.escape_reason[i] > last_escape_reason))
      throw bad(escape, "orbit " + std::to_string(j) + " has escape reason " +
                            std::to_string(e.escape_reason[i]));
    if (at >= 0) continue;
    for (std::size_t k = 0; k < names.size(); ++k)
      if (!std::isfinite(e.state[k][i]))
        throw bad(state, "orbit " + std::to_string(j) + " has not escaped but its " +
                             std::string(names[k]) + " is not finite");
    for (std::size_t c = 0; c < e.columns.size(); ++c)
      if (!(e.columns[c][i] >= e.column_specs[c].least) || !std::isfinite(e.columns[c][i]))
        throw bad(root, "orbit " + std::to_string(j) + " has not escaped but its " +
                            e.column_specs[c].path + " is " + number_text(e.columns[c][i]) +
                            (std::isfinite(e.columns[c][i])
                                 ? ", below its least value " + number_text(e.column_specs[c].least)
                                 : std::string()));
    if (const auto why = model.invalid_record(e, i); !why.empty())
      throw bad(state, "orbit " + std::to_string(j) + ": " + why);
  }
  e.fill_padding();
}

void restore_observers(const h5::Group& root, Observers& o, Rows rows) {
  const bool counts_here = ranks::root();  // each histogram's counts, once over the ranks
  if (!o.densities.empty()) {
    const auto histograms = root.open_group("histograms");
    for (auto& d : o.densities)
      if (counts_here) restore_histogram(histograms.open_group(d.histogram.name()), "counts", d.histogram);
  }
  if (o.sections.empty()) return;
  const auto sections = root.open_group("sections");
  for (auto& s : o.sections) {
    const auto g = sections.open_group(s.name);
    if (counts_here) restore_histogram(g, "density", s.density);
    if (s.mode == SectionMode::exact && counts_here) {
      if (!g.has_attr("interpolated")) throw bad(g, "it has no attribute interpolated");
      s.interpolated = g.attr_int64("interpolated");
      if (s.interpolated < 0 || s.interpolated > s.density.samples())
        throw bad(g, "interpolated is " + std::to_string(s.interpolated) + ", not 0 to crossings");
    }
    // The points kept per orbit, each within the orbit's slots, say how many points there are:
    // this process's follow those of the orbits before its rows.
    SectionPoints& kept = *s.points;
    const Rows orbits = rows.or_all(kept.kept().size());
    const auto counts = read_column<std::int64_t>(g, "kept", orbits.first, orbits.count, orbits.total);
    std::size_t points = 0;
    for (const std::int64_t k : counts) {
      if (k < 0 || k > kept.per_orbit())
        throw bad(g, "an orbit keeps " + std::to_string(k) + " points, not 0 to " +
                         std::to_string(kept.per_orbit()));
      points += static_cast<std::size_t>(k);
    }
    const auto mine = static_cast<std::int64_t>(points);
    const auto before = static_cast<std::size_t>(ranks::before(mine));
    const auto total = static_cast<std::size_t>(ranks::sum(mine));
    const auto orbit = read_column<std::int64_t>(g, "orbit", before, points, total);
    const auto step = read_column<std::int64_t>(g, "step", before, points, total);
    const auto x = read_column<double>(g, "x", before, points, total);
    const auto y = read_column<double>(g, "y", before, points, total);
    // Each orbit's points in step order, orbit after orbit, as many as it keeps.
    kept.clear();
    const auto first = static_cast<std::int64_t>(orbits.first);
    for (std::size_t i = 0; i < points; ++i) {
      const bool ordered = i == 0 || orbit[i] > orbit[i - 1] ||
                           (orbit[i] == orbit[i - 1] && step[i] > step[i - 1]);
      if (!ordered || orbit[i] < first ||
          static_cast<std::size_t>(orbit[i] - first) >= counts.size() || step[i] < 1 ||
          !std::isfinite(x[i]) || !std::isfinite(y[i]))
        throw bad(g, "point " + std::to_string(before + i) + " is not one a run records");
      kept.keep(static_cast<std::size_t>(orbit[i] - first), step[i], x[i], y[i]);
    }
    if (!std::ranges::equal(counts, kept.kept()))
      throw bad(g, "its points are not spread over the orbits as kept says");
  }
}

}  // namespace qmaps
