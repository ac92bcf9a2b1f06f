// The tangent map of every map, from its own step run on Dual values (core/dual.hpp):
// - its Jacobian agrees with central differences of the step computed in long double;
// - the values it computes are the plain step's, bit for bit, and a batch's lanes give the
//   scalar's bits (values and derivatives);
// - det J = 1 for the maps that preserve volume in their state's coordinates (Suris and case2,
//   whose q_{n+1} = F(q_n) − q_{n−1}; the flow's symplectic compositions); case2-hky's det J is
//   its oscillators' closed form, not 1; case3's implicit quartic is a variational map in u, whose
//   invariant volume has a varying density: its det J is reported.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <type_traits>

#include "core/dual.hpp"
#include "core/params.hpp"
#include "kernels/maps.hpp"

namespace qmaps {
namespace {

// A tolerance against an independent reference: central differences in long double with a step
// of 1e-6 (truncation ~1e-12, round-off ~1e-13 relative), against derivatives exact to round-off.
constexpr double finite_difference_tolerance = 1e-8;
// det J of a volume-preserving map, from the tangent map in double: round-off only.
constexpr double volume_tolerance = 1e-12;

template <class Map>
typename Map::Coeffs example_coefficients() {
  const auto values = resolve_params(Map::name, Map::params, param_values(Map::facts.example));
  return Map::coefficients(values);
}

// A generic state of a bounded orbit: 7 steps from a point of the example box.
template <class Map>
typename Map::template State<double> generic_state(const typename Map::Coeffs& c) {
  auto s = Map::from_phase_space(c, Phase{0.31, -0.22, 0.13, 0.27}, Start::taylor);
  for (int n = 0; n < 7; ++n) Map::step(c, s);
  return s;
}

template <class Map, class V, std::size_t S = std::tuple_size_v<typename Map::template State<double>>>
std::array<Dual<V, S>, S> tangent_of_identity(const typename Map::Coeffs& c,
                                              const std::array<V, S>& s) {
  std::array<std::array<V, S>, S> identity{};
  for (std::size_t j = 0; j < S; ++j) {
    identity[j].fill(V(0.0));
    identity[j][j] = V(1.0);
  }
  auto x = with_deviations<S>(s, identity);
  Map::step(c, x);
  return x;
}

// Determinant by Gaussian elimination with partial pivoting, in long double.
template <std::size_t S>
long double determinant(std::array<std::array<long double, S>, S> a) {
  long double det = 1;
  for (std::size_t col = 0; col < S; ++col) {
    std::size_t pivot = col;
    for (std::size_t r = col + 1; r < S; ++r)
      if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
    if (a[pivot][col] == 0) return 0;
    if (pivot != col) {
      std::swap(a[pivot], a[col]);
      det = -det;
    }
    det *= a[col][col];
    for (std::size_t r = col + 1; r < S; ++r) {
      const long double f = a[r][col] / a[col][col];
      for (std::size_t k = col; k < S; ++k) a[r][k] -= f * a[col][k];
    }
  }
  return det;
}

TEST(Tangent, JacobianOfEveryMapAgreesWithLongDoubleCentralDifferencesWithinTolerance) {
  kernels::for_each_map([](auto map) {
    using Map = decltype(map);
    const auto c = example_coefficients<Map>();
    const auto s = generic_state<Map>(c);
    constexpr std::size_t S = std::tuple_size_v<decltype(s)>;
    const auto x = tangent_of_identity<Map, double>(c, s);
    double worst = 0;
    for (std::size_t j = 0; j < S; ++j) {
      std::array<long double, S> plus, minus;
      for (std::size_t k = 0; k < S; ++k) plus[k] = minus[k] = s[k];
      const long double e = 1e-6L * std::max(1.0L, std::fabs(static_cast<long double>(s[j])));
      plus[j] += e;
      minus[j] -= e;
      Map::step(c, plus);
      Map::step(c, minus);
      for (std::size_t k = 0; k < S; ++k) {
        const long double reference = (plus[k] - minus[k]) / (2 * e);
        const double error = static_cast<double>(std::fabs(x[k].d[j] - reference) /
                                                 (1 + std::fabs(reference)));
        worst = std::max(worst, error);
        EXPECT_LE(error, finite_difference_tolerance)
            << Map::name << ": dx" << k << "/dx" << j << " " << x[k].d[j] << " vs "
            << static_cast<double>(reference);
      }
    }
    std::printf("[ jacobian ] %-16s max |J - J_fd|/(1 + |J_fd|) = %.1e (bound %.0e)\n",
                std::string(Map::name).c_str(), worst, finite_difference_tolerance);
  });
}

TEST(Tangent, TangentStepLeavesTheValuesBitIdenticalToThePlainStep) {
  kernels::for_each_map([](auto map) {
    using Map = decltype(map);
    const auto c = example_coefficients<Map>();
    auto s = generic_state<Map>(c);
    auto x = tangent_of_identity<Map, double>(c, s);
    Map::step(c, s);
    for (std::size_t k = 0; k < s.size(); ++k)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(x[k].v), std::bit_cast<std::uint64_t>(s[k]))
          << Map::name << " component " << k;
  });
}

// Each lane of an SSE2 batch (the ISA every x86-64 build has) gives the scalar path's bits for
// the value and every derivative.
TEST(Tangent, BatchLanesGiveTheScalarBits) {
  using B = xsimd::batch<double, xsimd::sse2>;
  kernels::for_each_map([](auto map) {
    using Map = decltype(map);
    const auto c = example_coefficients<Map>();
    const auto s0 = generic_state<Map>(c);
    auto s1 = s0;
    Map::step(c, s1);  // a second orbit, one step on
    constexpr std::size_t S = std::tuple_size_v<decltype(s0)>;
    std::array<B, S> batch;
    for (std::size_t k = 0; k < S; ++k) {
      alignas(16) const double two[2] = {s0[k], s1[k]};
      batch[k] = B::load_aligned(two);
    }
    const auto xb = tangent_of_identity<Map, B>(c, batch);
    const auto x0 = tangent_of_identity<Map, double>(c, s0);
    const auto x1 = tangent_of_identity<Map, double>(c, s1);
    for (std::size_t k = 0; k < S; ++k)
      for (std::size_t j = 0; j < S; ++j) {
        const auto lanes = ops::lanes_of(xb[k].d[j]);
        EXPECT_EQ(std::bit_cast<std::uint64_t>(lanes[0]), std::bit_cast<std::uint64_t>(x0[k].d[j]))
            << Map::name;
        EXPECT_EQ(std::bit_cast<std::uint64_t>(lanes[1]), std::bit_cast<std::uint64_t>(x1[k].d[j]))
            << Map::name;
      }
  });
}

TEST(Tangent, VolumePreservingMapsHaveUnitJacobianDeterminant) {
  kernels::for_each_map([](auto map) {
    using Map = decltype(map);
    const auto c = example_coefficients<Map>();
    const auto s = generic_state<Map>(c);
    const auto x = tangent_of_identity<Map, double>(c, s);
    // The phase-space part: the first 4 components (case3's t and λ ride along: λ is constant
    // and t never feeds back into u).
    std::array<std::array<long double, 4>, 4> j{};
    for (std::size_t r = 0; r < 4; ++r)
      for (std::size_t k = 0; k < 4; ++k) j[r][k] = x[r].d[k];
    const double det = static_cast<double>(determinant(j));
    if constexpr (std::is_same_v<Map, kernels::Case3>) {
      std::printf("[ det J ] %-16s %.17g (a variational map in u: it keeps its own symplectic "
                  "form, whose density varies, not du)\n", std::string(Map::name).c_str(), det);
    } else if constexpr (std::is_same_v<Map, kernels::Case2Hky>) {
      // Each oscillator u± (x, y) -> (y, z), z = (k1 y − x f)/(f + k3 xy), f = k0 + k2 y², has
      // det = −∂z/∂x = (f² + k1k3 y²)/(f + k3 xy)²: not 1 where k3 ≠ 0 (the map keeps a measure
      // with a density instead). The change q -> u± is linear: the product is det J.
      long double expected = 1;
      for (int sign : {1, -1}) {
        const long double x = s[0] + sign * s[1], y = s[2] + sign * s[3];
        const long double f = c.k0 + c.k2 * y * y, den = f + c.k3 * x * y;
        expected *= (f * f + c.k1 * c.k3 * y * y) / (den * den);
      }
      std::printf("[ det J ] %-16s %.17g (the oscillators' formula: %.17g)\n",
                  std::string(Map::name).c_str(), det, static_cast<double>(expected));
      EXPECT_NEAR(det, static_cast<double>(expected), volume_tolerance);
    } else {
      std::printf("[ det J ] %-16s %.17g\n", std::string(Map::name).c_str(), det);
      EXPECT_NEAR(det, 1.0, volume_tolerance) << Map::name;
    }
  });
}

}  // namespace
}  // namespace qmaps
