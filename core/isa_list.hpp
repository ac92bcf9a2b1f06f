#pragma once
// The one list of SIMD instruction sets, narrowest first, one entry per line. Everything else
// derives from it: the build reads each entry's name, lanes and compiler flags (CMakeLists.txt),
// core/isa.hpp its enum, lane counts and CPU test, core/dispatch.hpp each ISA's xsimd architecture.
//
// Fields: name, xsimd architecture, lanes (doubles per register), whether this CPU has it, flags.
// clang-format off
#define QMAPS_FOR_EACH_ISA(X) \
  X(sse2,   xsimd::sse2,              2, __builtin_cpu_supports("sse2"), "-msse2") \
  X(avx2,   xsimd::fma3<xsimd::avx2>, 4, __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"), "-mavx2 -mfma") \
  X(avx512, xsimd::avx512f,           8, __builtin_cpu_supports("avx512f"), "-mavx512f -mavx2 -mfma")
// clang-format on
