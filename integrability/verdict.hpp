#pragma once
// The three integrability tests of one map and their verdict (docs/integrability.md): degree
// growth, orbits over finite fields, height growth. Each test says integrable, not integrable or
// undecided; the verdict is the tests' where they agree, the degree test's where the others are
// undecided (it is the sharpest: an exact sequence, fitted exactly), and undecided where any two
// decided tests disagree, naming them.
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "integrability/degree_growth.hpp"
#include "integrability/exact_map.hpp"
#include "integrability/finite_field_orbits.hpp"
#include "integrability/height_growth.hpp"
#include "integrability/options.hpp"

namespace qmaps::exact {

enum class Says { integrable, not_integrable, undecided };
std::string to_string(Says s);

// The finite-field test at the largest prime: the periods follow R (a reversible map that is not
// integrable) where the sample cannot tell them from R (p-value at least `significance`) or they
// lie within near_R of it (the finite-field corrections of the Hénon maps and the leapfrog at the
// default sizes are 0.025–0.04); they are far from it at a distance of far_from_R or more, with
// a p-value below `significance`; between, undecided.
// Fewer than min_periods periods decide nothing.
inline constexpr double near_R = 0.05, far_from_R = 0.1, significance = 0.01;
inline constexpr std::size_t min_periods = 100;

struct Report {
  std::string map, evaluated_by;
  std::vector<std::string> varying, invariant_names;
  bool invariants_exact = false;
  DegreeTest degrees;
  std::vector<FieldOrbits> fields;
  HeightTest heights;
  Says degree_says = Says::undecided, field_says = Says::undecided, height_says = Says::undecided;
  Says verdict = Says::undecided;
  bool tests_agree = false;
  std::string reason;
};

// The options' defaults filled in for this map (primes by its dimension), checked: a number that
// is not prime, or too large for its arithmetic, is a usage error naming the option.
IntegrabilityOptions resolved(const IntegrabilityOptions& o, const ExactMap& map);
Report integrability_report(const ExactMap& map, const IntegrabilityOptions& resolved_options);
void write_text(std::ostream& out, const Report& r);

}  // namespace qmaps::exact
