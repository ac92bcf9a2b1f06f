#pragma once
// e^x for double and batches, one algorithm (the formulas' exp; core/ops.hpp has log, sin_cos):
//   k = nearest(x/ln2),  r = (x − k·ln2_hi) − k·ln2_lo   (ln2_hi's low 21 bits 0: k·ln2_hi exact),
//   e^r = Σ_{n≤13} rⁿ/n!  on |r| ≤ ln2/2 (the tail < 1e-17 relative),
//   e^x = e^r · 2^⌊k/2⌋ · 2^(k − ⌊k/2⌋)   (two normal factors: the result overflows to +inf
//   past x ≈ 709.78 and underflows through the subnormals to 0 below x ≈ −745.13).
// NaN gives NaN.
#include <array>
#include <bit>
#include <cstdint>
#include <limits>

#include "core/ops.hpp"

namespace qmaps::ops {

// 2^j for an integer-valued j in [−1022, 1023]: its exponent field written directly (for batches:
// j + 1023 + 2^52 holds j + 1023 in its low bits, shifted to the exponent's place).
template <std::floating_point T>
inline T power_of_two(T j) {
  return std::bit_cast<double>(static_cast<std::uint64_t>(static_cast<std::int64_t>(j) + 1023) << 52);
}
template <class A>
inline batch<A> power_of_two(batch<A> j) {
  using Bits = xsimd::batch<std::uint64_t, A>;
  const auto biased = xsimd::bitwise_cast<Bits>(j + batch<A>(1023.0 + 0x1p52));
  if constexpr (detail::form<A> == detail::Form::avx512f)  // the masked form, as ops.hpp's
    return xsimd::bitwise_cast<batch<A>>(Bits(_mm512_maskz_slli_epi64(0xFF, biased, 52)));
  else
    return xsimd::bitwise_cast<batch<A>>(Bits(biased << 52));
}

template <class V>
inline V exp(V x) {
  constexpr double ln2_hi = std::bit_cast<double>(std::uint64_t{0x3fe62e42fee00000});
  constexpr double ln2_lo = static_cast<double>(0.693147180559945309417232121458176568L - ln2_hi);
  // 1/n!, n ≤ 13, each exact below 2^53 before its division
  constexpr auto inverse_factorials = [] {
    std::array<double, 14> c{};
    double factorial = 1;
    for (int n = 0; n < 14; ++n) {
      if (n > 0) factorial *= n;
      c[static_cast<std::size_t>(n)] = 1.0 / factorial;
    }
    return c;
  }();
  // k within the halves' range (and 0 for NaN, whose result is x)
  const V bounded = ops::select(x == x, ops::min(ops::max(x, V(-746.0)), V(710.0)), V(0.0));
  const V k = ops::floor(bounded * V(1.44269504088896340735992468100189214) + V(0.5));
  const V r = (bounded - k * V(ln2_hi)) - k * V(ln2_lo);
  V p(inverse_factorials[13]);
  for (int n = 12; n >= 0; --n) p = ops::fma(p, r, V(inverse_factorials[static_cast<std::size_t>(n)]));
  const V half = ops::floor(k * V(0.5));
  const V result = (p * ops::power_of_two(half)) * ops::power_of_two(k - half);
  return ops::select(x == x, result, x);
}

}  // namespace qmaps::ops
