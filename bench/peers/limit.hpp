#pragma once
// The limit loops (limit_isa.cpp), one per instruction set, each in its own translation unit:
// call one only where the CPU has its ISA. x: the four state columns of n orbits, n a multiple of
// 8 × limit_chains.
#include <cstddef>

namespace qmaps::peers {

inline constexpr int limit_chains = 4;

void limit_avx512(double* const x[4], std::size_t n, long long steps, double two_a, double two_b,
                  double g, int threads);
void limit_avx2(double* const x[4], std::size_t n, long long steps, double two_a, double two_b,
                double g, int threads);

}  // namespace qmaps::peers
