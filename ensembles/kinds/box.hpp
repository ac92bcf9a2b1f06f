#pragma once
// The `box` ensemble: (q1, q2, p1, p2) uniform in given ranges, orbit i drawn by Philox from
// (seed, i) alone. A range given as one number fixes that coordinate.
#include <array>
#include <cstdint>

#include "ensembles/kinds/ensemble_kind.hpp"

namespace qmaps {

class Box final : public EnsembleKind {
 public:
  // Reads [ensemble] orbits, seed, q1, q2, p1, p2.
  explicit Box(const Config& config);
  using Ranges = std::array<std::array<double, 2>, 4>;  // q1, q2, p1, p2: [lo, hi]
  Box(const Ranges& ranges, std::uint64_t seed, std::size_t orbits)
      : ranges_(ranges), seed_(seed), orbits_(orbits) {}
  std::size_t orbits() const override { return orbits_; }
  Drawn draw(std::size_t orbit) const override;
  std::string description() const override;
  std::uint64_t seed() const override { return seed_; }

 private:
  Ranges ranges_;
  std::uint64_t seed_;
  std::size_t orbits_;
};

}  // namespace qmaps
