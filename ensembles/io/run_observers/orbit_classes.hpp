#pragma once
// Orbits counted by class: regular or chaotic (by an indicator and its threshold) or escaped, and
// the chaotic fraction of those that did not escape (NaN where none is left).
#include <cstdint>

#include "ensembles/io/measured_output.hpp"

namespace qmaps {

struct OrbitClasses {
  std::int64_t regular = 0, chaotic = 0, escaped = 0;
  double chaotic_fraction() const { return MeasuredOutput::share(chaotic, regular + chaotic); }
};

}  // namespace qmaps
