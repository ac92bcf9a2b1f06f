// The limit: the Suris map (suris_peer.hpp) written by hand with one instruction set's intrinsics,
// the state of K × W orbits held in registers for all the steps (W lanes, K = 4 or 8 independent
// chains to hide the latency of the division), OpenMP over blocks:
//   z = fms(two_a·y, 1/(1 + g|y|²), x)   per component
// Compiled twice (bench/CMakeLists.txt), each time alone with its ISA's flags:
// QMAPS_LIMIT_BITS = 512 (-mavx512f -mfma) defines limit_avx512, 256 (-mavx2 -mfma) limit_avx2.
#include <immintrin.h>

#include "limit.hpp"

#if QMAPS_LIMIT_BITS == 512
#define QMAPS_MM(op) _mm512_##op
#define QMAPS_LIMIT_NAME limit_avx512
using Register = __m512d;
#elif QMAPS_LIMIT_BITS == 256
#define QMAPS_MM(op) _mm256_##op
#define QMAPS_LIMIT_NAME limit_avx2
using Register = __m256d;
#else
#error "QMAPS_LIMIT_BITS must be 512 or 256"
#endif

namespace qmaps::peers {

namespace {

template <int K>
void limit_loop(double* const x[4], std::size_t n, long long steps, double two_a, double two_b,
                double g, int threads) {
  constexpr std::size_t W = sizeof(Register) / sizeof(double);
  constexpr std::size_t block = W * K;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t b = 0; b < n; b += block) {
    Register q1p[K], q2p[K], q1[K], q2[K];
    const Register va = QMAPS_MM(set1_pd)(two_a), vb = QMAPS_MM(set1_pd)(two_b),
                   vg = QMAPS_MM(set1_pd)(g), one = QMAPS_MM(set1_pd)(1.0);
    for (int k = 0; k < K; ++k) {
      const std::size_t o = b + W * k;
      q1p[k] = QMAPS_MM(loadu_pd)(x[0] + o), q2p[k] = QMAPS_MM(loadu_pd)(x[1] + o);
      q1[k] = QMAPS_MM(loadu_pd)(x[2] + o), q2[k] = QMAPS_MM(loadu_pd)(x[3] + o);
    }
    for (long long s = 0; s < steps; ++s)
      for (int k = 0; k < K; ++k) {
        const Register r = QMAPS_MM(fmadd_pd)(q2[k], q2[k], QMAPS_MM(mul_pd)(q1[k], q1[k]));
        const Register inv = QMAPS_MM(div_pd)(one, QMAPS_MM(fmadd_pd)(vg, r, one));
        const Register n1 = QMAPS_MM(fmsub_pd)(QMAPS_MM(mul_pd)(va, q1[k]), inv, q1p[k]);
        const Register n2 = QMAPS_MM(fmsub_pd)(QMAPS_MM(mul_pd)(vb, q2[k]), inv, q2p[k]);
        q1p[k] = q1[k], q2p[k] = q2[k], q1[k] = n1, q2[k] = n2;
      }
    for (int k = 0; k < K; ++k) {
      const std::size_t o = b + W * k;
      QMAPS_MM(storeu_pd)(x[0] + o, q1p[k]), QMAPS_MM(storeu_pd)(x[1] + o, q2p[k]);
      QMAPS_MM(storeu_pd)(x[2] + o, q1[k]), QMAPS_MM(storeu_pd)(x[3] + o, q2[k]);
    }
  }
}

}  // namespace

void QMAPS_LIMIT_NAME(double* const x[4], std::size_t n, long long steps, double two_a,
                      double two_b, double g, int threads, int chains) {
  if (chains == 8)
    limit_loop<8>(x, n, steps, two_a, two_b, g, threads);
  else
    limit_loop<4>(x, n, steps, two_a, two_b, g, threads);
}

}  // namespace qmaps::peers
