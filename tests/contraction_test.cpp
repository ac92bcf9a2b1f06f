// Floating-point contraction is off in every kernel translation unit: a·b + c, written as two
// operations there, must round twice. With a = 1 + 2⁻³⁰, b = 1 − 2⁻³⁰, c = −1 the exact product
// is 1 − 2⁻⁶⁰: rounded it is 1 and the sum is 0; fused into one FMA the result would be −2⁻⁶⁰.
// Every map of kernels/maps.hpp on every ISA the build compiled and this CPU runs.
#include <gtest/gtest.h>

#include <cmath>

#include "core/dispatch.hpp"
#include "isas_run.hpp"
#include "kernels/maps.hpp"

namespace qmaps {
namespace {

TEST(Contraction, KernelTranslationUnitsRoundMultiplyAndAddSeparately) {
  const double a = 1 + std::ldexp(1.0, -30), b = 1 - std::ldexp(1.0, -30), c = -1;
  ASSERT_NE(std::fma(a, b, c), 0.0) << "the probe's inputs must tell fused from unfused";
  const auto isas = testing::isas_to_run();
  kernels::for_each_map([&]<class Map>(Map) {
    for (Isa isa : isas) {
      const auto [batch, scalar] = simd_path<Map>(isa).contraction_probe(a, b, c);
      EXPECT_EQ(batch, 0.0) << "batch a*b+c contracted in the " << Map::name << " "
                            << isa_name(isa) << " unit";
      EXPECT_EQ(scalar, 0.0) << "scalar a*b+c contracted in the " << Map::name << " "
                             << isa_name(isa) << " unit";
      std::cout << "[ probed ] " << Map::name << ' ' << isa_name(isa) << '\n';
    }
  });
}

}  // namespace
}  // namespace qmaps
