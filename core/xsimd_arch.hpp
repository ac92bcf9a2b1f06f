#pragma once
// The xsimd architecture behind each of our ISAs (avx2 means AVX2 with FMA).
#include <cstddef>

#include <xsimd/xsimd.hpp>

#include "core/isa.hpp"

namespace qmaps {

template <Isa isa>
struct arch_for;
template <>
struct arch_for<Isa::sse2> { using type = xsimd::sse2; };
template <>
struct arch_for<Isa::avx2> { using type = xsimd::fma3<xsimd::avx2>; };
template <>
struct arch_for<Isa::avx512> { using type = xsimd::avx512f; };

template <Isa isa>
using arch_of = typename arch_for<isa>::type;

}  // namespace qmaps
