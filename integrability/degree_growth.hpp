#pragma once
// Degree growth, or algebraic entropy (docs/integrability.md): the map iterated over F_p(t) from a
// random line x0 + t·v of initial conditions, each iterate's numerators and denominators divided
// by their gcd (field.hpp's FunctionOfT, FLINT). d_n is the largest degree in t of the state's
// coordinates after n steps (d_0 = 1). Over several primes and lines, which must agree (a line or
// prime that is not generic shows lower degrees), and the growth of the sequence fitted
// (growth_fit.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include "integrability/exact_map.hpp"
#include "integrability/growth_fit.hpp"

namespace qmaps::exact {

struct DegreeSequence {
  std::uint64_t prime = 0;
  int line = 0;
  std::vector<double> degrees;  // d_0 … d_n
  std::string stopped;          // why before the steps asked for: the cap, a singular line
};

struct DegreeTest {
  std::vector<DegreeSequence> runs;  // primes × lines
  bool agree = true;                 // every run the same sequence (as far as the shortest)
  Growth growth;                     // of the first run's sequence
  int steps = 0;
  long cap = 0;
};

DegreeSequence degree_sequence(const ExactMap& map, std::uint64_t prime, int line, int steps,
                               long cap, std::uint64_t seed);
DegreeTest degree_test(const ExactMap& map, const std::vector<std::uint64_t>& primes, int lines,
                       int steps, long cap, std::uint64_t seed);

}  // namespace qmaps::exact
