#pragma once
// The invariant image ([invariant_image]): the 2D histogram of two invariants' initial values
// over the ensemble, written with the run (/invariants/image).
#include "core/observers/histogram.hpp"

namespace qmaps {

struct InvariantImage {
  Histogram histogram;  // axes' coordinates are the invariants' names
};

}  // namespace qmaps
