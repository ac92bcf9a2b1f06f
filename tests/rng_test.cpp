// Counter-based draws: Philox4x64-10 reproduces Random123's known-answer vector, and the box
// ensemble's orbit i depends on (seed, i) alone, never on threads or order.
#include <gtest/gtest.h>

#include <omp.h>

#include <cstdint>

#include "core/rng.hpp"
#include "ensembles/kinds/box.hpp"
#include "ensembles/kinds/initial_conditions.hpp"

namespace qmaps {
namespace {

TEST(Rng, PhiloxMatchesRandom123KnownAnswerVector) {
  // kat_vectors: philox4x64 10, counter 0, key 0 → 16554d9eca36314c db20fe9d672d0fdc ...
  const auto u = OrbitRandom(0, 0).uniform4(0, 0);
  const std::uint64_t expected[4] = {0x16554d9eca36314cULL, 0xdb20fe9d672d0fdcULL,
                                     0xd7e772cee186176bULL, 0x7e68b68aec7ba23bULL};
  for (int k = 0; k < 4; ++k) EXPECT_EQ(u[k], static_cast<double>(expected[k] >> 11) * 0x1.0p-53);
}

TEST(Rng, DrawsAreInUnitIntervalAndDifferByOrbitSeedAndStream) {
  const OrbitRandom a(1, 2);
  for (std::uint64_t i = 0; i < 1000; ++i)
    for (double x : a.uniform4(i)) {
      EXPECT_GE(x, 0.0);
      EXPECT_LT(x, 1.0);
    }
  EXPECT_NE(a.uniform4(0), a.uniform4(1));
  EXPECT_NE(a.uniform4(0), OrbitRandom(2, 2).uniform4(0));
  EXPECT_NE(a.uniform4(0), OrbitRandom(1, 3).uniform4(0));
  EXPECT_EQ(a.uniform4(5), OrbitRandom(1, 2).uniform4(5));
}

TEST(Box, OrbitIDependsOnSeedAndIndexAloneNotOnThreads) {
  const Box box({{{-1, 1}, {0.25, 0.25}, {2, 3}, {-0.5, 0.5}}}, 42, 10007);
  const auto one = generate(box, 1).points;
  const auto two = generate(box, 2, 3).points;
  for (std::size_t i = 0; i < box.orbits(); i += 997) {
    const Phase x = box.draw(i).point;
    EXPECT_EQ(one[i].q1, x.q1);
    EXPECT_EQ(two[i].p2, x.p2);
    EXPECT_EQ(x.q2, 0.25) << "a degenerate range is the fixed value";
    EXPECT_GE(x.q1, -1.0);
    EXPECT_LT(x.q1, 1.0);
    EXPECT_GE(x.p1, 2.0);
    EXPECT_LT(x.p1, 3.0);
  }
  // Hand-computed: orbit 3 is the Philox draw of (seed 42, stream "box", counter 3).
  const auto u = OrbitRandom(42, 0x626f78).uniform4(3);
  EXPECT_EQ(box.draw(3).point.q1, -1 + 2 * u[0]);
  EXPECT_EQ(box.draw(3).point.p1, 2 + 1 * u[2]);
}

}  // namespace
}  // namespace qmaps
