#include "ensembles/io/checkpoint.hpp"

#include <cmath>
#include <stdexcept>

#include "core/error.hpp"
#include "core/escape.hpp"
#include "core/version.hpp"
#include "ensembles/io/run_observers/run_observers.hpp"

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
  write_kept(root, describe_kept(record), rows);
  file.close();
  out.commit();
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
  if (e.step < 0) throw state.error("step " + std::to_string(e.step));
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t i = first + j;
    const std::int64_t at = e.escape_step[i];
    if (at < -1 || at > e.step)
      throw escape.error("orbit " + std::to_string(j) + " escaped at step " + std::to_string(at));
    if (at < 0 && e.escape_reason[i] != 0)
      throw escape.error("orbit " + std::to_string(j) + " has not escaped but has escape reason " +
                         std::to_string(e.escape_reason[i]));
    if (at >= 0 && (e.escape_reason[i] == 0 || e.escape_reason[i] > last_escape_reason))
      throw escape.error("orbit " + std::to_string(j) + " has escape reason " +
                         std::to_string(e.escape_reason[i]));
    if (at >= 0) continue;
    for (std::size_t k = 0; k < names.size(); ++k)
      if (!std::isfinite(e.state[k][i]))
        throw state.error("orbit " + std::to_string(j) + " has not escaped but its " +
                          std::string(names[k]) + " is not finite");
    for (std::size_t c = 0; c < e.columns.size(); ++c)
      if (!(std::isnan(e.columns[c][i]) && e.column_specs[c].may_be_nan) &&
          (!(e.columns[c][i] >= e.column_specs[c].least) || !std::isfinite(e.columns[c][i])))
        throw root.error("orbit " + std::to_string(j) + " has not escaped but its " +
                         e.column_specs[c].path + " is " + number_text(e.columns[c][i]) +
                         (std::isfinite(e.columns[c][i])
                              ? ", below its least value " + number_text(e.column_specs[c].least)
                              : std::string()));
    if (const auto why = model.invalid_record(e, i); !why.empty())
      throw state.error("orbit " + std::to_string(j) + ": " + why);
  }
  e.fill_padding();
}

}  // namespace qmaps
