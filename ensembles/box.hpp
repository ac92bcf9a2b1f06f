#pragma once
// The `box` ensemble: (q1, q2, p1, p2) uniform in given ranges, orbit i drawn by Philox from
// (seed, i) alone.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/config.hpp"
#include "core/phase.hpp"

namespace qmaps {

struct Box {
  std::array<std::array<double, 2>, 4> ranges;  // q1, q2, p1, p2: [lo, hi]
  std::uint64_t seed = 0;
  std::size_t orbits = 0;

  static Box from_config(const Config& config);  // reads [ensemble] orbits, seed, q1, q2, p1, p2
  Phase point(std::size_t orbit) const;
  // Orbits [first, first + out.size()).
  void points(std::size_t first, std::span<Phase> out) const;
  std::vector<Phase> points() const;
};

}  // namespace qmaps
