#pragma once
// A run's checkpoint, "<output>.ckpt" (docs/hdf5-schema.md): the file of the run so far, as
// write_run writes it with every per-orbit dataset (so the ensemble's state, escapes, invariant
// tracking and the observers' histograms and section points), plus the run's /initial points
// and what the run observers keep besides (measured_output.hpp, write_kept). Resuming reads the
// state itself, never the ensemble's generator, and goes on exactly where the run stopped.
#include <cstdint>
#include <string>

#include "core/ensemble.hpp"
#include "ensembles/io/h5.hpp"
#include "core/model.hpp"
#include "core/observers/observers.hpp"
#include "ensembles/io/output.hpp"

namespace qmaps {

inline constexpr std::int64_t checkpoint_version = 1;
inline constexpr const char* checkpoint_suffix = ".ckpt";

// Writes the checkpoint atomically (a temporary renamed to `path`). `initial`, when not null, is
// the run's /initial group, copied into the checkpoint.
void write_checkpoint(const std::string& path, RunRecord record, const h5::Group* initial);

// The checkpoint at `path`, opened for reading once it is known to be one this qmaps can resume.
h5::File open_checkpoint(const std::string& path);
// Fills orbits [at, at + rows.count) of `e` (laid out for the checkpoint's map) with the file's
// rows [rows.first, rows.first + rows.count) of rows.total, and e.step with its step. By default
// (count 0) the file's orbits are all of e's: a checkpoint's own ensemble. A shard's go to its
// place `at` in the whole run's; a rank of qmaps-mpi reads its rows of the run's checkpoint.
void read_ensemble(const h5::Group& root, const Model& model, Ensemble& e, Rows rows = {},
                   std::size_t at = 0);
}  // namespace qmaps
