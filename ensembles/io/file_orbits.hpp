#pragma once
// The number of orbits a run file says it holds (its `orbits` attribute), checked before any
// dataset is read by it: not negative, and its per-orbit data within the memory limit. A file's
// datasets are then read only at that length (h5::Group::read_doubles and the like).
#include <cstddef>
#include <string>

#include "ensembles/io/h5.hpp"

namespace qmaps {

std::size_t orbits_in(const h5::Group& root, const std::string& path, double bytes_per_orbit);

}  // namespace qmaps
