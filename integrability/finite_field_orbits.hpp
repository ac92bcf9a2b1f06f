#pragma once
// Orbits over a finite field (Roberts–Vivaldi; docs/integrability.md): the map over F_p^d (d the
// coordinates its step changes), from random points, each orbit stepped until it returns to its
// start (its period T), meets a point where a denominator vanishes mod p (counted apart), or runs
// past max_period. Lanes::lanes orbits at once (ResidueLanes); the point of orbit i depends on (seed, i)
// alone, so the periods do not depend on the threads.
//
// The statistic: a reversible map that is not integrable has, as p grows, the periods of a
// composition of two random involutions: the fraction of points on orbits with T ≤ x·λ tends to
// R(x) = 1 − e^(−x)(1 + x), with λ = 2N/#(Fix G ∪ Fix H). R is the law of a Gamma(2, 1) variable,
// whose mean is 2, so λ is estimated as half the mean period of points drawn uniformly; the
// Kolmogorov–Smirnov distance D between the periods over λ and R, and its p-value by a parametric
// bootstrap (200 samples of R of the same size, fewer beyond 10^4 periods, each scaled by its own
// mean, as the data are). An
// integrable map's orbits lie on the level sets of its invariants, whose periods follow another
// law: D stays large as p grows. Where the map's invariants are exact, the orbits of the first
// block are checked to keep every invariant's value mod p at every step.
#include <cstdint>
#include <string>
#include <vector>

#include "integrability/exact_map.hpp"

namespace qmaps::exact {

struct FieldOrbits {
  std::uint64_t prime = 0;
  std::size_t dimension = 0;
  std::vector<std::uint64_t> periods;  // of the orbits that returned, in orbit order
  std::size_t orbits = 0, singular = 0, unfinished = 0;  // unfinished: past max_period
  std::uint64_t max_period = 0;
  double steps = 0;                   // map steps taken, over all orbits
  double lambda = 0;                  // mean period / 2
  double ks_distance = 0, p_value = 1;  // against R(x)
  // Level sets: orbits of the first block whose every invariant kept its value at every step,
  // of those checked (none checked where the invariants are not exact).
  std::size_t level_checked = 0, level_kept = 0;
};

FieldOrbits finite_field_orbits(const ExactMap& map, std::uint64_t prime, std::size_t orbits,
                                std::uint64_t max_period, std::uint64_t seed);
// Orbit i's starting point: the changing coordinates uniform in F_p, the others 0.
std::array<std::uint64_t, 4> orbit_start(const ExactMap& map, std::uint64_t seed, std::uint64_t i,
                                         std::uint64_t p);
// Orbit i's starting point: the changing coordinates uniform in F_p, the others 0.
std::array<std::uint64_t, 4> orbit_start(const ExactMap& map, std::uint64_t seed, std::uint64_t i,
                                         std::uint64_t p);
// R(x) = 1 − e^(−x)(1 + x)
double universal_law(double x);

}  // namespace qmaps::exact
