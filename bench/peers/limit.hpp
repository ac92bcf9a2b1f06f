#pragma once
// The limit loops (limit_isa.cpp), one per instruction set, each in its own translation unit:
// call one only where the CPU has its ISA. x: the four state columns of n orbits, n a multiple of
// 8 × chains; chains: 4 or 8.
#include <cstddef>

namespace qmaps::peers {

void limit_avx512(double* const x[4], std::size_t n, long long steps, double two_a, double two_b,
                  double g, int threads, int chains);
void limit_avx2(double* const x[4], std::size_t n, long long steps, double two_a, double two_b,
                double g, int threads, int chains);

}  // namespace qmaps::peers
