#pragma once
// The sizes of the three integrability tests (verdict.hpp), apart from the tests themselves so
// that what only passes them on (the command line, ensembles/program/commands.hpp) compiles
// without the exact arithmetic.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace qmaps::exact {

struct IntegrabilityOptions {
  // degree growth
  std::vector<std::uint64_t> degree_primes;  // empty: two primes near 2^61
  int lines = 2;
  int steps = 30;
  long degree_cap = 20000;
  // finite fields
  std::vector<std::uint64_t> field_primes;  // empty: three primes, by the map's dimension
  std::size_t orbits = 1000;  // where fewer than half come back, up to 20 times as many
  std::uint64_t max_period = 0;  // 0: 64 p^(d/2)
  // heights
  int height_steps = 40;
  double height_bits = 1 << 20;
  std::uint64_t seed = 1;
};

}  // namespace qmaps::exact
