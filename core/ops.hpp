#pragma once
// The value-type layer: every kernel computes through these functions, written once for a scalar
// (double, long double) and for an xsimd batch of doubles, with the same algorithm on both so that
// a lane of a batch and the scalar reference round identically, bit for bit.
//
//   +, -, *, /      IEEE operators of the type itself (correctly rounded on every path)
//   fma(a, b, c)    a·b + c rounded once: hardware FMA where the ISA has it, std::fma per lane else
//   fms(a, b, c)    a·b − c rounded once, likewise
//   neg(a)          −a exactly, signed zeros included. Never write unary minus on a batch:
//                   xsimd 8's AVX-512 negation is 0 − a, which maps +0 to +0.
//   sqrt, abs, floor  correctly rounded / exact on every path
//   log             natural log, one algorithm written below for every type (a long double's is
//                   the C library's): within 2 ulp of the C library's log (measured over
//                   80 binades), the same bits everywhere
//   sin_cos         sine and cosine for |x| ≤ 2^20, one algorithm written below for every type
//   any, all, bits  of a mask; bits: lane l's in bit l
//   select, max, min  per-lane choice; max(a, b) = b > a ? b : a, NaN handling identical everywhere
//                     (one maxpd / minpd on a batch, whose operand order gives exactly that rule)
//   integer_lanes     the lanes of a value holding exact integers in [0, 2^52), as integers
//   compress(p, m, v) the lanes of v where m holds, stored packed from p in lane order (p has
//                     room for a whole batch: the lanes after them are overwritten); their count
//   lane_index<V>()   each lane's index, as a value
//
// A batch's op is chosen by its xsimd architecture A (core/isa_list.hpp names one per ISA), never
// by its lane count: form<A> is AVX-512F at 512 bits, AVX2 with FMA at 256 bits, SSE2 at 128 bits
// (A or an architecture derived from it, as xsimd derives sse4_2 from sse2), or the fallback, which
// is correct for any other architecture (a 4-lane ISA without FMA takes std::fma per lane). Every
// ISA of the list must take one of the three forms (checked below).
//
// This is the only file that touches xsimd or intrinsics.
#include <array>
#include <bit>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

#include "core/isa_list.hpp"

namespace qmaps::ops {

template <class V>
struct traits;

template <std::floating_point T>
struct traits<T> {
  using scalar = T;
  using mask = bool;
  static constexpr std::size_t lanes = 1;
};

template <class A>
struct traits<xsimd::batch<double, A>> {
  using scalar = double;
  using mask = xsimd::batch_bool<double, A>;
  static constexpr std::size_t lanes = xsimd::batch<double, A>::size;
};

template <class V>
using mask_t = typename traits<V>::mask;
template <class V>
inline constexpr std::size_t lanes = traits<V>::lanes;

// ---- scalar ---------------------------------------------------------------------------------
template <std::floating_point T>
inline T fma(T a, T b, T c) { return std::fma(a, b, c); }
template <std::floating_point T>
inline T fms(T a, T b, T c) { return std::fma(a, b, -c); }
template <std::floating_point T>
inline T sqrt(T a) { return std::sqrt(a); }
template <std::floating_point T>
inline T abs(T a) { return std::fabs(a); }
template <std::floating_point T>
inline T floor(T a) { return std::floor(a); }
// a = m · 2^e with m in [0.5, 1) (exact; a normal or subnormal, > 0), e as a value of T.
template <std::floating_point T>
inline T split_exponent(T a, T& e) {
  int k;
  const T m = std::frexp(a, &k);
  e = static_cast<T>(k);
  return m;
}
template <std::floating_point T>
inline T select(bool m, T a, T b) { return m ? a : b; }
inline bool any(bool m) { return m; }
inline std::uint64_t bits(bool m) { return m ? 1 : 0; }  // lane l's in bit l
inline bool all(bool m) { return m; }
inline bool negate(bool m) { return !m; }

template <std::floating_point T>
inline T load(const double* p) { return static_cast<T>(*p); }
template <std::floating_point T>
inline void store(double* p, T v) { *p = static_cast<double>(v); }
template <std::floating_point T>
inline std::array<double, 1> lanes_of(T v) { return {static_cast<double>(v)}; }
inline std::array<bool, 1> lanes_of(bool m) { return {m}; }
template <std::floating_point T>
inline std::size_t compress(double* p, bool m, T v) {
  *p = static_cast<double>(v);
  return m ? 1 : 0;
}

// ---- batch ----------------------------------------------------------------------------------
template <class A>
using batch = xsimd::batch<double, A>;

namespace detail {
// The form an architecture's ops take. xsimd 8 derives avx512f and sse2 from generic, avx2 from
// avx and fma3<avx2> from avx2 (not avx512f from fma3<avx2>), and its x86 architectures align to
// their register's width: an architecture is tested for its base and its width, the widest first.
enum class Form { avx512f, avx2_fma, sse2, fallback };
template <class A>
inline constexpr Form form =
    std::is_base_of_v<xsimd::avx512f, A> && A::alignment() == 64               ? Form::avx512f
    : std::is_base_of_v<xsimd::fma3<xsimd::avx2>, A> && A::alignment() == 32   ? Form::avx2_fma
    : std::is_base_of_v<xsimd::sse2, A> && A::alignment() == 16                ? Form::sse2
                                                                               : Form::fallback;
template <class A>
inline constexpr std::size_t form_lanes = form<A> == Form::avx512f    ? 8
                                          : form<A> == Form::avx2_fma ? 4
                                          : form<A> == Form::sse2     ? 2
                                                                      : 0;  // the fallback
// Every ISA of the list takes the form of its width, never the fallback.
#define QMAPS_OPS_FORM_OF(name, arch, lanes, ...) \
  static_assert(form_lanes<arch> == lanes, #name ": no form of its width in core/ops.hpp");
QMAPS_FOR_EACH_ISA(QMAPS_OPS_FORM_OF)
#undef QMAPS_OPS_FORM_OF

// Applies std::fma to each lane, with c negated when `subtract`: the exactly rounded fallback
// for an ISA without an FMA unit. Not inlined (nor per_lane): each use is then one call, which cuts
// an SSE2 unit's code by 40% and its compile time by a quarter; the library's fma costs more.
template <class A>
[[gnu::noinline]] batch<A> fma_per_lane(batch<A> a, batch<A> b, batch<A> c, bool subtract) {
  alignas(64) std::array<double, batch<A>::size> x, y, z;
  a.store_aligned(x.data());
  b.store_aligned(y.data());
  c.store_aligned(z.data());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::fma(x[i], y[i], subtract ? -z[i] : z[i]);
  return batch<A>::load_aligned(x.data());
}
// Applies the scalar op f to each lane: the fallback's sqrt and floor.
template <class A, class F>
[[gnu::noinline]] batch<A> per_lane(batch<A> a, F f) {
  alignas(64) std::array<double, batch<A>::size> x;
  a.store_aligned(x.data());
  for (double& v : x) v = f(v);
  return batch<A>::load_aligned(x.data());
}
}  // namespace detail

template <class A>
inline batch<A> fma(batch<A> a, batch<A> b, batch<A> c) {
  if constexpr (detail::form<A> == detail::Form::avx512f) {
    return _mm512_fmadd_pd(a, b, c);  // xsimd 8 falls back to a·b + c on avx512f: not fused
  } else if constexpr (detail::form<A> == detail::Form::avx2_fma) {
    return _mm256_fmadd_pd(a, b, c);
  } else {
    return detail::fma_per_lane(a, b, c, false);
  }
}
template <class A>
inline batch<A> fms(batch<A> a, batch<A> b, batch<A> c) {
  if constexpr (detail::form<A> == detail::Form::avx512f) {
    return _mm512_fmsub_pd(a, b, c);
  } else if constexpr (detail::form<A> == detail::Form::avx2_fma) {
    return _mm256_fmsub_pd(a, b, c);
  } else {
    return detail::fma_per_lane(a, b, c, true);
  }
}
template <class A>
inline batch<A> sqrt(batch<A> a) {
  if constexpr (detail::form<A> == detail::Form::avx512f)
    return _mm512_maskz_sqrt_pd(0xFF, a);  // xsimd's form reads an undefined register
  else if constexpr (detail::form<A> != detail::Form::fallback)
    return xsimd::sqrt(a);
  else
    return detail::per_lane(a, [](double x) { return std::sqrt(x); });
}
template <class A>
inline batch<A> abs(batch<A> a) { return xsimd::abs(a); }
template <class A>
inline batch<A> floor(batch<A> a) {
  if constexpr (detail::form<A> == detail::Form::avx512f)  // xsimd's form: an undefined register
    return _mm512_maskz_roundscale_pd(0xFF, a, _MM_FROUND_TO_NEG_INF);
  else if constexpr (detail::form<A> == detail::Form::avx2_fma)
    return xsimd::floor(a);
  else if constexpr (detail::form<A> == detail::Form::sse2)  // xsimd's SSE2 floor truncates
    return xsimd::floor(a) | (a & batch<A>(-0.0));  // through integers: −0 needs its sign back
  else
    return detail::per_lane(a, [](double x) { return std::floor(x); });
}
template <class A>
inline batch<A> split_exponent(batch<A> a, batch<A>& e) {  // normal a only: log scales the rest
  if constexpr (detail::form<A> == detail::Form::avx512f) {  // both parts exactly, as doubles
    e = batch<A>(_mm512_maskz_getexp_pd(0xFF, a)) + batch<A>(1.0);
    return _mm512_maskz_getmant_pd(0xFF, a, _MM_MANT_NORM_p5_1, _MM_MANT_SIGN_src);
  } else if constexpr (detail::form<A> != detail::Form::fallback) {
    xsimd::batch<std::int64_t, A> k;
    const batch<A> m = xsimd::frexp(a, k);
    e = xsimd::to_float(k);
    return m;
  } else {
    alignas(64) std::array<double, batch<A>::size> m, k;
    a.store_aligned(m.data());
    for (std::size_t l = 0; l < m.size(); ++l) m[l] = split_exponent(m[l], k[l]);
    e = batch<A>::load_aligned(k.data());
    return batch<A>::load_aligned(m.data());
  }
}
template <class A>
inline batch<A> select(xsimd::batch_bool<double, A> m, batch<A> a, batch<A> b) {
  return xsimd::select(m, a, b);
}
template <class A>
inline bool any(xsimd::batch_bool<double, A> m) { return xsimd::any(m); }
template <class A>
inline bool all(xsimd::batch_bool<double, A> m) { return xsimd::all(m); }
template <class A>
inline std::uint64_t bits(xsimd::batch_bool<double, A> m) {
  if constexpr (detail::form<A> == detail::Form::avx512f) {
    return static_cast<__mmask8>(m);
  } else if constexpr (detail::form<A> == detail::Form::avx2_fma) {
    return static_cast<std::uint64_t>(_mm256_movemask_pd(m));
  } else if constexpr (detail::form<A> == detail::Form::sse2) {
    return static_cast<std::uint64_t>(_mm_movemask_pd(m));
  } else {
    std::array<bool, batch<A>::size> lanes;
    m.store_unaligned(lanes.data());
    std::uint64_t out = 0;
    for (std::size_t l = 0; l < lanes.size(); ++l) out |= std::uint64_t{lanes[l]} << l;
    return out;
  }
}
template <class A>
inline xsimd::batch_bool<double, A> negate(xsimd::batch_bool<double, A> m) { return !m; }

template <class V>
  requires(!std::floating_point<V>)
inline V load(const double* p) { return V::load_aligned(p); }
template <class A>
inline void store(double* p, batch<A> v) { v.store_aligned(p); }
template <class A>
inline std::array<double, batch<A>::size> lanes_of(batch<A> v) {
  alignas(64) std::array<double, batch<A>::size> out;
  v.store_aligned(out.data());
  return out;
}
template <class A>
inline std::array<bool, batch<A>::size> lanes_of(xsimd::batch_bool<double, A> m) {
  std::array<bool, batch<A>::size> out;
  m.store_unaligned(out.data());
  return out;
}

namespace detail {
// For each 4-lane mask, the 32-bit halves of its lanes first, in order: one permute packs them.
inline constexpr auto packed_halves = [] {
  std::array<std::array<std::int32_t, 8>, 16> order{};
  for (int m = 0; m < 16; ++m) {
    int j = 0;
    for (int l = 0; l < 4; ++l)
      if (m >> l & 1) {
        order[m][2 * j] = 2 * l;
        order[m][2 * j + 1] = 2 * l + 1;
        ++j;
      }
  }
  return order;
}();
}  // namespace detail

template <class A>
inline std::size_t compress(double* p, xsimd::batch_bool<double, A> m, batch<A> v) {
  const std::uint64_t b = bits(m);
  if constexpr (detail::form<A> == detail::Form::avx512f) {
    _mm512_storeu_pd(p, _mm512_maskz_compress_pd(static_cast<__mmask8>(b), v));
    return static_cast<std::size_t>(std::popcount(b));
  } else if constexpr (detail::form<A> == detail::Form::avx2_fma) {
    const __m256i order = _mm256_loadu_si256(
        reinterpret_cast<const __m256i*>(detail::packed_halves[b].data()));
    _mm256_storeu_pd(p, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), order)));
    return static_cast<std::size_t>(std::popcount(b));
  } else if constexpr (detail::form<A> == detail::Form::sse2) {
    _mm_storeu_pd(p, b == 2 ? _mm_unpackhi_pd(v, v) : __m128d(v));
    return static_cast<std::size_t>((b & 1) + (b >> 1));
  } else {
    const auto x = lanes_of(v);
    std::size_t n = 0;
    for (std::size_t l = 0; l < x.size(); ++l) {
      p[n] = x[l];
      n += b >> l & 1;
    }
    return n;
  }
}

// maxpd(x, y) = x > y ? x : y and minpd(x, y) = x < y ? x : y (the second operand on equality
// or NaN), so max(a, b) = maxpd(b, a) and min(a, b) = minpd(b, a), as the scalar rule below; the
// fallback selects by that rule.
template <class A>
inline batch<A> max(batch<A> a, batch<A> b) {
  if constexpr (detail::form<A> == detail::Form::avx512f)
    return _mm512_maskz_max_pd(0xFF, b, a);  // the unmasked form reads an undefined register
  else if constexpr (detail::form<A> == detail::Form::avx2_fma)
    return _mm256_max_pd(b, a);
  else if constexpr (detail::form<A> == detail::Form::sse2)
    return _mm_max_pd(b, a);
  else
    return xsimd::select(b > a, b, a);
}
template <class A>
inline batch<A> min(batch<A> a, batch<A> b) {
  if constexpr (detail::form<A> == detail::Form::avx512f)
    return _mm512_maskz_min_pd(0xFF, b, a);
  else if constexpr (detail::form<A> == detail::Form::avx2_fma)
    return _mm256_min_pd(b, a);
  else if constexpr (detail::form<A> == detail::Form::sse2)
    return _mm_min_pd(b, a);
  else
    return xsimd::select(b < a, b, a);
}

// ---- written once for both --------------------------------------------------------------------
template <std::floating_point T>
inline T max(T a, T b) { return b > a ? b : a; }
template <std::floating_point T>
inline T min(T a, T b) { return b < a ? b : a; }
// v + 2^52 is exact for an integer v in [0, 2^52) and holds v in its low 52 bits: one addition
// for all lanes instead of a conversion per lane.
template <class V>
inline std::array<std::uint64_t, lanes<V>> integer_lanes(V v) {
  constexpr std::uint64_t low52 = (std::uint64_t{1} << 52) - 1;
  std::array<std::uint64_t, lanes<V>> out;
  if constexpr (std::floating_point<V>) {
    out[0] = std::bit_cast<std::uint64_t>(static_cast<double>(v) + 0x1p52) & low52;
  } else {  // the mask applied to the whole register
    const auto bits = lanes_of((v + V(0x1p52)) & V(std::bit_cast<double>(low52)));
    for (std::size_t l = 0; l < out.size(); ++l) out[l] = std::bit_cast<std::uint64_t>(bits[l]);
  }
  return out;
}
template <class V>
inline V square(V a) { return a * a; }
template <class V>
inline V lane_index() {
  if constexpr (std::floating_point<V>) {
    return V(0.0);
  } else {
    alignas(64) std::array<double, lanes<V>> index;
    for (std::size_t l = 0; l < index.size(); ++l) index[l] = static_cast<double>(l);
    return load<V>(index.data());
  }
}

// ln a for double and batches, one algorithm: a = m·2^e with m in [√½, √2) (subnormals scaled by
// 2^200 first, exactly), f = m − 1, s = f/(2 + f), and
//   ln a = e·ln2 + 2s (1 + s²/3 + s⁴/5 + … + s²⁰/21)     |s| ≤ 0.1716: the series' tail < 1e-18
// with ln2 = hi + lo, hi's low 21 bits 0 so that e·hi is exact. 0 → −inf, +inf → +inf, else NaN.
template <class V>
inline V log(V a) {
  if constexpr (std::is_same_v<V, long double>) {
    return std::log(a);
  } else {
    const auto tiny = a < V(0x1p-1000);
    V e;
    V m = ops::split_exponent(ops::select(tiny, a * V(0x1p200), a), e);
    e = ops::select(tiny, e - V(200.0), e);
    const auto low = m < V(0.70710678118654752440);
    m = ops::select(low, m + m, m);
    e = ops::select(low, e - V(1.0), e);
    const V f = m - V(1.0);
    const V s = f / (V(2.0) + f);
    const V z = s * s;
    // Σ_{k≤9} z^k/(2k + 3) by Estrin's scheme: 4 dependent operations instead of Horner's 9 (the
    // indicators' step is latency-bound on it)
    const auto c = [](int k) { return V(1.0 / (2 * k + 3)); };
    const V z2 = z * z, z4 = z2 * z2, z8 = z4 * z4;
    const V p01 = ops::fma(c(1), z, c(0)), p23 = ops::fma(c(3), z, c(2)),
            p45 = ops::fma(c(5), z, c(4)), p67 = ops::fma(c(7), z, c(6)),
            p89 = ops::fma(c(9), z, c(8));
    const V first8 = ops::fma(ops::fma(p67, z2, p45), z4, ops::fma(p23, z2, p01));
    const V series = ops::fma(p89, z8, first8);
    const V two_s = s + s;
    const V log_m = ops::fma(two_s * z, series, two_s);
    constexpr double ln2_hi = std::bit_cast<double>(std::uint64_t{0x3fe62e42fee00000});
    constexpr double ln2_lo = static_cast<double>(0.693147180559945309417232121458176568L - ln2_hi);
    const V result = ops::fma(e, V(ln2_hi), ops::fma(e, V(ln2_lo), log_m));
    const V inf(std::numeric_limits<double>::infinity());
    const V special = ops::select(a == V(0.0), V(0.0) - inf,
                             ops::select(a == inf, inf, V(std::numeric_limits<double>::quiet_NaN())));
    return ops::select((a > V(0.0)) & (a < inf), result, special);
  }
}
// −0 − a: exact negation (+0 → −0, −0 → +0), the same arithmetic on every path.
template <class V>
inline V neg(V a) { return V(-0.0) - a; }

// sin x and cos x for |x| ≤ 2^20 (the tunes' angles: at most 2π), one algorithm for double and
// batches: k = nearest(x·2/π), y = x − k·π/2 with π/2 in three parts of 33 bits (Cody and
// Waite: each k·part exact), then on |y| ≤ π/4
//   sin y = y (1 − y²/3! + … − y¹⁶/17!),  cos y = 1 − y²/2! + … + y¹⁸/18!   tails < 1e-19
// and the quadrant k mod 4 picks ±sin y or ±cos y.
template <class V>
inline void sin_cos(V x, V& sine, V& cosine) {
  const V k = ops::floor(x * V(0.636619772367581343075535053490057448) + V(0.5));
  const V y = ((x - k * V(1.57079632673412561417e+00)) - k * V(6.07710050630396597660e-11)) -
              k * V(2.02226624871116645580e-21);
  // (−1)^j/(2j + 1)! and (−1)^j/(2j)!, each n! exact below 2^53
  constexpr auto terms = [] {
    std::array<double, 9> odd{};
    std::array<double, 10> even{};
    double factorial = 1;
    for (int n = 0; n <= 18; ++n) {
      if (n > 0) factorial *= n;
      const double term = ((n / 2) % 2 ? -1.0 : 1.0) / factorial;
      if (n % 2) odd[n / 2] = term;
      else even[n / 2] = term;
    }
    return std::pair{odd, even};
  }();
  const V z = y * y;
  V s(terms.first[8]), c(terms.second[9]);
  for (int j = 7; j >= 1; --j) s = ops::fma(s, z, V(terms.first[j]));
  for (int j = 8; j >= 1; --j) c = ops::fma(c, z, V(terms.second[j]));
  s = ops::fma(y * z, s, y);
  c = ops::fma(z, c, V(1.0));
  const V quadrant = k - V(4.0) * ops::floor(k * V(0.25));
  const auto odd = (quadrant == V(1.0)) | (quadrant == V(3.0));
  const V a = ops::select(odd, c, s), b = ops::select(odd, s, c);
  sine = ops::select(quadrant >= V(2.0), ops::neg(a), a);
  cosine = ops::select((quadrant == V(1.0)) | (quadrant == V(2.0)), ops::neg(b), b);
}

}  // namespace qmaps::ops
