// The preset peer: the default preset's work (preset.hpp) on the Suris map, written by hand with
// one instruction set's intrinsics. The limit's loop (limit_isa.cpp): K × W orbits in registers
// (W lanes, K = 4 or 8 chains), OpenMP over blocks; a block advances in chunks of up to 256 steps:
//   every step    each chain's lanes that cross q1 = 0 upward (q1_n < 0 ≤ q1_{n+1}, read before
//                 the step) packed by a compress, with their place (step, chain, lane);
//   every stride  H, I1, I2 and their drift max |I − I(0)|, and the (q1, q2) density, of one
//                 chain per step after it;
//   each chunk    the packed lanes W at a time: p2 from a reversed step, the section's density,
//                 the points while the orbit has fewer than the cap;
//   the end       the last state's invariants, and the image of the initial (H, I1).
// The histograms count into 32-bit cells per thread (a run's counts on one thread stay below
// 2^32), added to the run's when the thread is done. The arithmetic is qmaps' (kernels/suris.hpp;
// the binning of core/observers/histogram_lanes.hpp), so the counts and values are too
// (preset_bench checks them). No escape test, as the limit: the preset's orbits are bounded.
// Compiled twice (bench/peers/CMakeLists.txt), each time alone with its ISA's flags:
// QMAPS_PRESET_BITS = 512 (-mavx512f -mfma) defines preset_avx512, 256 (-mavx2 -mfma) preset_avx2.
#include <immintrin.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <vector>

#include "preset.hpp"

namespace qmaps::peers {
namespace {

#if QMAPS_PRESET_BITS == 512
#define QMAPS_PRESET_NAME preset_avx512
using Register = __m512d;
using Mask = __mmask8;
constexpr std::size_t W = 8;
Register set1(double x) { return _mm512_set1_pd(x); }
Register load(const double* p) { return _mm512_loadu_pd(p); }
void store(double* p, Register v) { _mm512_storeu_pd(p, v); }
Register add(Register a, Register b) { return _mm512_add_pd(a, b); }
Register sub(Register a, Register b) { return _mm512_sub_pd(a, b); }
Register mul(Register a, Register b) { return _mm512_mul_pd(a, b); }
Register div(Register a, Register b) { return _mm512_div_pd(a, b); }
Register fmadd(Register a, Register b, Register c) { return _mm512_fmadd_pd(a, b, c); }
Register fmsub(Register a, Register b, Register c) { return _mm512_fmsub_pd(a, b, c); }
// The masked forms where the unmasked ones read an undefined register (GCC 12 warns).
Register max(Register a, Register b) { return _mm512_maskz_max_pd(0xFF, a, b); }
Register min(Register a, Register b) { return _mm512_maskz_min_pd(0xFF, a, b); }
Register abs(Register a) { return _mm512_abs_pd(a); }
Register floor(Register a) { return _mm512_maskz_roundscale_pd(0xFF, a, _MM_FROUND_TO_NEG_INF); }
Register lane_index() { return _mm512_set_pd(7, 6, 5, 4, 3, 2, 1, 0); }
Mask less(Register a, Register b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
Mask at_least(Register a, Register b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
Mask both(Mask a, Mask b) { return a & b; }
Mask either(Mask a, Mask b) { return a | b; }
unsigned bits(Mask m) { return m; }
Register select(Mask m, Register a, Register b) { return _mm512_mask_blend_pd(m, b, a); }
void store_integers(std::int32_t* p, Register v) {  // truncated
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), _mm512_maskz_cvttpd_epi32(0xFF, v));
}
// The lanes of v where m holds, stored packed from p (the W doubles from p are written).
std::size_t compress(double* p, Mask m, Register v) {
  _mm512_storeu_pd(p, _mm512_maskz_compress_pd(m, v));
  return static_cast<std::size_t>(std::popcount(bits(m)));
}
#elif QMAPS_PRESET_BITS == 256
#define QMAPS_PRESET_NAME preset_avx2
using Register = __m256d;
using Mask = __m256d;
constexpr std::size_t W = 4;
Register set1(double x) { return _mm256_set1_pd(x); }
Register load(const double* p) { return _mm256_loadu_pd(p); }
void store(double* p, Register v) { _mm256_storeu_pd(p, v); }
Register add(Register a, Register b) { return _mm256_add_pd(a, b); }
Register sub(Register a, Register b) { return _mm256_sub_pd(a, b); }
Register mul(Register a, Register b) { return _mm256_mul_pd(a, b); }
Register div(Register a, Register b) { return _mm256_div_pd(a, b); }
Register fmadd(Register a, Register b, Register c) { return _mm256_fmadd_pd(a, b, c); }
Register fmsub(Register a, Register b, Register c) { return _mm256_fmsub_pd(a, b, c); }
Register max(Register a, Register b) { return _mm256_max_pd(a, b); }
Register min(Register a, Register b) { return _mm256_min_pd(a, b); }
Register abs(Register a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
Register floor(Register a) { return _mm256_floor_pd(a); }
Register lane_index() { return _mm256_set_pd(3, 2, 1, 0); }
Mask less(Register a, Register b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
Mask at_least(Register a, Register b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
Mask both(Mask a, Mask b) { return _mm256_and_pd(a, b); }
Mask either(Mask a, Mask b) { return _mm256_or_pd(a, b); }
unsigned bits(Mask m) { return static_cast<unsigned>(_mm256_movemask_pd(m)); }
Register select(Mask m, Register a, Register b) { return _mm256_blendv_pd(b, a, m); }
void store_integers(std::int32_t* p, Register v) {  // truncated
  _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm256_cvttpd_epi32(v));
}
// For each mask of 4 lanes, the 32-bit halves of the lanes it holds, first.
constexpr auto packed_halves = [] {
  std::array<std::array<std::int32_t, 8>, 16> t{};
  for (int m = 0; m < 16; ++m)
    for (int l = 0, n = 0; l < 4; ++l)
      if (m >> l & 1) t[m][2 * n] = 2 * l, t[m][2 * n + 1] = 2 * l + 1, ++n;
  return t;
}();
// The lanes of v where m holds, stored packed from p (the W doubles from p are written).
std::size_t compress(double* p, Mask m, Register v) {
  const unsigned b = bits(m);
  const __m256i order =
      _mm256_loadu_si256(reinterpret_cast<const __m256i*>(packed_halves[b].data()));
  _mm256_storeu_pd(p, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), order)));
  return static_cast<std::size_t>(std::popcount(b));
}
#else
#error "QMAPS_PRESET_BITS must be 512 or 256"
#endif

// A histogram's binning, as qmaps bins: the slot of (x, y) is its cell (row-major), else the
// underflow (below lo on either axis) or the overflow (at or above hi, or NaN).
struct Binning {
  Register lo0, lo1, hi0, hi1, scale0, scale1, last, bins, underflow, overflow;
  explicit Binning(const PresetRange& r)
      : lo0(set1(r.lo[0])), lo1(set1(r.lo[1])), hi0(set1(r.hi[0])), hi1(set1(r.hi[1])),
        scale0(set1(preset_bins / (r.hi[0] - r.lo[0]))),
        scale1(set1(preset_bins / (r.hi[1] - r.lo[1]))), last(set1(preset_bins - 1)),
        bins(set1(preset_bins)), underflow(set1(preset_counts - 2)),
        overflow(set1(preset_counts - 1)) {}
  Register slot(Register x, Register y) const {
    const Mask below = either(less(x, lo0), less(y, lo1));
    const Mask inside = both(less(x, hi0), less(y, hi1));
    const Register cell = add(mul(min(floor(mul(sub(x, lo0), scale0)), last), bins),
                              min(floor(mul(sub(y, lo1), scale1)), last));
    return select(below, underflow, select(inside, cell, overflow));
  }
};

// Counts the first `lanes` lanes' slots.
inline void count(std::uint32_t* counts, Register slots, std::size_t lanes) {
  alignas(32) std::int32_t s[W];
  store_integers(s, slots);
  for (std::size_t l = 0; l < lanes; ++l) ++counts[s[l]];
}

constexpr long long chunk = 256;
// The packed crossings' room per column (q1, q2, q2_{n+1}, place): every lane of a chunk, and W.
template <int K>
constexpr std::size_t room = chunk * W * K + W;

template <int K>
void preset_block(const PresetCoeffs& c, const PresetRun& r, std::size_t first_orbit,
                  const Binning (&binning)[3], std::uint32_t* const (&counts)[3],
                  double* staged) {
  constexpr std::size_t block = W * K;
  const Register va = set1(c.two_a), vb = set1(c.two_b), vg = set1(c.g), one = set1(1.0),
                 zero = set1(0.0);
  Register s[K][4], initial[K][3], drift[K][3], chain_lanes[K];
#pragma GCC unroll 8
  for (int k = 0; k < K; ++k) {
    const std::size_t o = first_orbit + W * k;
    for (int i = 0; i < 4; ++i) s[k][i] = load(r.x[i] + o);
    for (int i = 0; i < 3; ++i)
      initial[k][i] = load(r.initial[i] + o), drift[k][i] = load(r.drift[i] + o);
    chain_lanes[k] = add(set1(static_cast<double>(W * k)), lane_index());
  }
  const auto step = [&](Register (&x)[4]) {
    const Register inv = div(one, fmadd(vg, fmadd(x[3], x[3], mul(x[2], x[2])), one));
    const Register z1 = fmsub(mul(va, x[2]), inv, x[0]), z2 = fmsub(mul(vb, x[3]), inv, x[1]);
    x[0] = x[2], x[1] = x[3], x[2] = z1, x[3] = z2;
  };
  // H, I1, I2 of (u, v) = (q_n, q_{n+1}), in kernels/suris.hpp's order of operations.
  const auto invariants = [&](const Register (&x)[4], Register (&out)[3]) {
    const Register u1 = x[0], u2 = x[1], v1 = x[2], v2 = x[3];
    const Register d1 = sub(v1, u1), d2 = sub(v2, u2), e1 = mul(d1, d1), e2 = mul(d2, d2);
    const Register w1 = mul(u1, v1), w2 = mul(u2, v2);
    const Register kinetic = mul(set1(c.half_inv_h2), add(e1, e2));
    const Register uu = fmadd(u2, u2, mul(u1, u1)), vv = fmadd(v2, v2, mul(v1, v1));
    out[0] = fmadd(mul(set1(c.Halpha), uu), vv,
                   fmadd(set1(c.HB), w2, fmadd(set1(c.HA), w1, kinetic)));
    const Register X = mul(v1, u2), Y = mul(u1, v2), XmY = sub(X, Y);
    const Register cross = mul(XmY, XmY), XY = mul(X, Y);
    const Register own1 = fmadd(w1, fmadd(vg, w1, set1(c.two_Ah2)), e1);
    const Register own2 = fmadd(w2, fmadd(vg, w2, set1(c.two_Bh2)), e2);
    out[1] = fmadd(set1(c.kx1), XY, fmadd(set1(c.k1), cross, own1));
    out[2] = fmadd(set1(c.kx2), XY, fmadd(set1(c.k2), cross, own2));
  };
  // The chains' states at the last sample's step, observed one chain per step after it (as
  // qmaps' block does), so that the observing overlaps the next steps' divisions.
  Register held[K][4];
  int unobserved = K;  // held[unobserved..K) are still to be observed
  const auto observe_one = [&] {
    if (unobserved == K) return;
    const int k = unobserved++;
    Register v[3];
    invariants(held[k], v);
    for (int i = 0; i < 3; ++i) drift[k][i] = max(abs(sub(v[i], initial[k][i])), drift[k][i]);
    count(counts[0], binning[0].slot(held[k][0], held[k][1]), W);
  };
  if (r.first == 0) {  // the density's sample at step 0
#pragma GCC unroll 8
    for (int k = 0; k < K; ++k) count(counts[0], binning[0].slot(s[k][0], s[k][1]), W);
  }

  long long to_sample = preset_stride - r.first % preset_stride;  // steps to the next sample
  for (long long from = 0; from < r.steps; from += chunk) {
    const long long to = std::min(r.steps, from + chunk);
    std::size_t packed = 0;
    for (long long j = from; j < to;) {
      const long long end = std::min(to, j + to_sample);
      to_sample -= end - j;
      for (; j < end; ++j) {
        Mask up[K];
        unsigned any = 0;
#pragma GCC unroll 8
        for (int k = 0; k < K; ++k) {
          up[k] = both(less(s[k][0], zero), at_least(s[k][2], zero));
          any |= bits(up[k]);
          step(s[k]);
        }
        if (any) {
          const Register at = set1(static_cast<double>((j - from) * static_cast<long long>(block)));
#pragma GCC unroll 8
          for (int k = 0; k < K; ++k) {
            if (!bits(up[k])) continue;
            double* p = staged + packed;
            compress(p, up[k], s[k][0]);
            compress(p + room<K>, up[k], s[k][1]);
            compress(p + 2 * room<K>, up[k], s[k][3]);
            packed += compress(p + 3 * room<K>, up[k], add(at, chain_lanes[k]));
          }
        }
        observe_one();
      }
      if (to_sample == 0) {
        while (unobserved < K) observe_one();  // a stride shorter than the chains
#pragma GCC unroll 8
        for (int k = 0; k < K; ++k)
          for (int i = 0; i < 4; ++i) held[k][i] = s[k][i];
        unobserved = 0;
        to_sample = preset_stride;
      }
    }
    // The chunk's crossings, each at node n + 1 = its state packed: (q2, p2), p2 =
    // (q2_{n+1} − q2_{n−1}) / 2h with q2_{n−1} a step of the reversed state (q_{n+1}, q_n).
    const Register two_h = set1(c.two_h);
    for (std::size_t i = 0; i < packed; i += W) {
      const Register q1 = load(staged + i), q2 = load(staged + room<K> + i),
                     q2_next = load(staged + 2 * room<K> + i);
      const Register inv = div(one, fmadd(vg, fmadd(q2, q2, mul(q1, q1)), one));
      const Register p2 = div(sub(q2_next, fmsub(mul(vb, q2), inv, q2_next)), two_h);
      alignas(32) std::int32_t slots[W], place[W];
      alignas(64) double x[W], y[W];
      store_integers(slots, binning[1].slot(q2, p2));
      store_integers(place, load(staged + 3 * room<K> + i));
      store(x, q2), store(y, p2);
      for (std::size_t l = 0; l < std::min(W, packed - i); ++l) {
        ++counts[1][slots[l]];
        const auto at = static_cast<std::size_t>(place[l]);
        const std::size_t o = first_orbit + at % block;
        std::int64_t& kept = r.kept[o];
        if (kept < preset_cap)
          r.points[o * preset_cap + static_cast<std::size_t>(kept++)] = {
              r.first + from + static_cast<long long>(at / block) + 1, x[l], y[l]};
      }
    }
  }
  while (unobserved < K) observe_one();
#pragma GCC unroll 8
  for (int k = 0; k < K; ++k) {
    const std::size_t o = first_orbit + W * k;
    Register v[3];
    invariants(s[k], v);
    for (int i = 0; i < 3; ++i) store(r.last[i] + o, v[i]), store(r.drift[i] + o, drift[k][i]);
    for (int i = 0; i < 4; ++i) store(r.x[i] + o, s[k][i]);
    count(counts[2], binning[2].slot(initial[k][0], initial[k][1]), W);
  }
}

template <int K>
void preset_loop(const PresetCoeffs& c, const PresetRun& r, int threads) {
  constexpr std::size_t block = W * K;
  const Binning binning[3] = {Binning(preset_density), Binning(preset_section),
                              Binning(preset_image)};
  std::uint64_t* const totals[3] = {r.density, r.section, r.image};
#pragma omp parallel num_threads(threads)
  {
    std::vector<std::uint32_t> mine(3 * preset_counts);  // this thread's counts
    std::uint32_t* const counts[3] = {mine.data(), mine.data() + preset_counts,
                                      mine.data() + 2 * preset_counts};
    std::vector<double> staged(4 * room<K>);
#pragma omp for schedule(static)
    for (std::size_t b = 0; b < r.n; b += block)
      preset_block<K>(c, r, b, binning, counts, staged.data());
#pragma omp critical
    for (int h = 0; h < 3; ++h)
      for (std::size_t i = 0; i < preset_counts; ++i) totals[h][i] += counts[h][i];
  }
}

}  // namespace

void QMAPS_PRESET_NAME(const PresetCoeffs& c, const PresetRun& r, int threads, int chains) {
  if (chains == 8)
    preset_loop<8>(c, r, threads);
  else
    preset_loop<4>(c, r, threads);
}

}  // namespace qmaps::peers
