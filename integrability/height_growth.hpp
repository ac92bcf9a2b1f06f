#pragma once
// Height growth (Diophantine integrability, docs/integrability.md): the map iterated exactly over Q
// (GMP) from a rational point of small height; h_n is the largest log height log max(|num|, |den|)
// of the state's coordinates after n steps. Integrable maps' log heights grow polynomially (as n²),
// others' exponentially; the growth is fitted by growth_fit.hpp's tail rules.
#include <cstdint>
#include <string>
#include <vector>

#include "integrability/exact_map.hpp"
#include "integrability/growth_fit.hpp"

namespace qmaps::exact {

struct HeightTest {
  std::vector<std::string> start;  // the rational starting point, by coordinate
  std::vector<double> log_heights;  // h_0 … h_n
  std::string stopped;              // why before the steps asked for
  Growth growth;
  int steps = 0;
  double max_bits = 0;
};

HeightTest height_test(const ExactMap& map, int steps, double max_bits, std::uint64_t seed);

}  // namespace qmaps::exact
