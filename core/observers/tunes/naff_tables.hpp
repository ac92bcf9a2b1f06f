#pragma once
// What the tunes' analysis (naff.hpp) needs of a window of N steps and Hann order p, computed once
// per thread by one scalar code for every path (ops::sin_cos): the weights of the window of order p
// over N steps and over its first M = N/4 steps (at least 64, at most N), where the line is searched,
//   w_n = sin^{2p}(π n / N)      (Laskar's window of order p, periodic at its ends),
// the curvature κ = Σ w m²/Σ w − (Σ w m/Σ w)² of a pure tone's |F|² at its peak (m = n − (N − 1)/2),
// and the FFT's twiddles e^{−2πi j/M} and bit-reversed order of M. And each thread's scratch
// memory: the signals recorded by each chain of a block and the FFT's, reused from block to block.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace qmaps {

struct NaffTables {
  long long n = 0;  // N, a power of two
  int order = 0;    // p
  std::vector<double> weight;  // over N
  double curvature = 0;        // κ
  std::size_t m = 0;           // M, a power of two
  std::vector<double> search_weight, cos_twiddle, sin_twiddle;  // over M; twiddles j < M/2
  std::vector<std::uint32_t> reversed;                          // the bit reversal of n < M
};

// The tables of (N, p) on this thread (the last ones asked for: a run has one window).
const NaffTables& naff_tables(long long n, int order);

// Scratch memory on this thread, 64-byte aligned, at least `doubles` long: slot `which` (a
// block's chain, or the FFT's: slot fft_slot). Its contents stay until the slot is asked for more.
inline constexpr std::size_t fft_slot = 8;
double* naff_scratch(std::size_t which, std::size_t doubles);

}  // namespace qmaps
