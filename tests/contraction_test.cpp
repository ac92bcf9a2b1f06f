// Floating-point contraction is off in every kernel translation unit: a·b + c, written as two
// operations there, must round twice. With a = 1 + 2⁻³⁰, b = 1 − 2⁻³⁰, c = −1 the exact product
// is 1 − 2⁻⁶⁰: rounded it is 1 and the sum is 0; fused into one FMA the result would be −2⁻⁶⁰.
#include <gtest/gtest.h>

#include <cmath>

#include "core/fp_probe.hpp"
#include "core/isa.hpp"
#include "core/xsimd_arch.hpp"
#include "kernels/case2.hpp"
#include "kernels/case2_hky.hpp"
#include "kernels/case3.hpp"
#include "kernels/flow.hpp"
#include "kernels/suris.hpp"

namespace qmaps {
namespace {

template <class Map>
std::array<double, 2> probe(Isa isa, double a, double b, double c) {
  switch (isa) {
#ifdef QMAPS_HAVE_SSE2
    case Isa::sse2: return contraction_probe<Map, arch_of<Isa::sse2>>(a, b, c);
#endif
#ifdef QMAPS_HAVE_AVX2
    case Isa::avx2: return contraction_probe<Map, arch_of<Isa::avx2>>(a, b, c);
#endif
#ifdef QMAPS_HAVE_AVX512
    case Isa::avx512: return contraction_probe<Map, arch_of<Isa::avx512>>(a, b, c);
#endif
    default: return {NAN, NAN};
  }
}

template <class Map>
void expect_uncontracted(double a, double b, double c) {
  for (Isa isa : runnable_isas()) {
    const auto [batch, scalar] = probe<Map>(isa, a, b, c);
    EXPECT_EQ(batch, 0.0) << "batch a*b+c contracted in the " << Map::name << " " << isa_name(isa) << " unit";
    EXPECT_EQ(scalar, 0.0) << "scalar a*b+c contracted in the " << Map::name << " " << isa_name(isa) << " unit";
    std::cout << "[ probed ] " << Map::name << ' ' << isa_name(isa) << '\n';
  }
}

TEST(Contraction, KernelTranslationUnitsRoundMultiplyAndAddSeparately) {
  const double a = 1 + std::ldexp(1.0, -30), b = 1 - std::ldexp(1.0, -30), c = -1;
  ASSERT_NE(std::fma(a, b, c), 0.0) << "the probe's inputs must tell fused from unfused";
  ASSERT_FALSE(runnable_isas().empty());
  expect_uncontracted<kernels::Suris>(a, b, c);
  expect_uncontracted<kernels::Case2>(a, b, c);
  expect_uncontracted<kernels::Case2Staggered>(a, b, c);
  expect_uncontracted<kernels::Case2Hky>(a, b, c);
  expect_uncontracted<kernels::Case3>(a, b, c);
  expect_uncontracted<kernels::Flow>(a, b, c);
  expect_uncontracted<kernels::Leapfrog>(a, b, c);
}

}  // namespace
}  // namespace qmaps
