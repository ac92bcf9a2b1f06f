#include "ensembles/box.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"

namespace qmaps {
namespace {
constexpr std::uint64_t box_stream = 0x626f78;  // "box"
}

Box Box::from_config(const Config& config) {
  Box box;
  const long long orbits = config.integer("ensemble", "orbits");
  if (orbits <= 0)
    throw usage_error(config.where("ensemble", "orbits") + " must be > 0 (got " +
                      std::to_string(orbits) + ")");
  box.orbits = static_cast<std::size_t>(orbits);
  const long long seed = config.integer_or("ensemble", "seed", 0);
  if (seed < 0) throw usage_error(config.where("ensemble", "seed") + " must be >= 0");
  box.seed = static_cast<std::uint64_t>(seed);
  const char* names[4] = {"q1", "q2", "p1", "p2"};
  for (int k = 0; k < 4; ++k) box.ranges[k] = config.range("ensemble", names[k]);
  return box;
}

Phase Box::point(std::size_t orbit) const {
  const auto u = OrbitRandom(seed, box_stream).uniform4(orbit);
  double x[4];
  for (int k = 0; k < 4; ++k) {
    const auto [lo, hi] = ranges[k];
    x[k] = lo == hi ? lo : lo + (hi - lo) * u[k];
  }
  return {x[0], x[1], x[2], x[3]};
}

void Box::points(std::size_t first, std::span<Phase> out) const {
  const long long n = static_cast<long long>(out.size());
#pragma omp parallel for schedule(static)
  for (long long i = 0; i < n; ++i) out[i] = point(first + static_cast<std::size_t>(i));
}

std::vector<Phase> Box::points() const {
  std::vector<Phase> out(orbits);
  points(0, out);
  return out;
}

}  // namespace qmaps
