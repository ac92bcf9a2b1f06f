#pragma once
// A contraction probe compiled into every per-ISA kernel translation unit: a·b + c written as two
// operations, in a batch and in a scalar. With -ffp-contract=off both round twice; a compiler
// allowed to contract would emit one fused multiply-add there (these units have FMA).
#include <array>

#include <xsimd/xsimd.hpp>

namespace qmaps {

template <class Map, class Arch>
std::array<double, 2> contraction_probe(double a, double b, double c)
#ifdef QMAPS_KERNEL_TRANSLATION_UNIT
{
  using V = xsimd::batch<double, Arch>;
  const V r = V(a) * V(b) + V(c);
  return {r.get(0), a * b + c};
}
#else
    ;
#endif

}  // namespace qmaps
