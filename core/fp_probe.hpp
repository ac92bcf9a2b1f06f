#pragma once
// The contraction probe, defined only in the per-ISA translation units (core/simd_unit.cpp.in):
// a·b + c written as two operations, in a batch and in a scalar. With -ffp-contract=off both round
// twice; a compiler allowed to contract would emit one fused multiply-add there (these units have
// FMA).
#include <array>

#include <xsimd/xsimd.hpp>

#include "core/dispatch.hpp"

namespace qmaps {

template <class Map, class Arch>
std::array<double, 2> contraction_probe(double a, double b, double c) {
  using V = xsimd::batch<double, Arch>;
  const V r = V(a) * V(b) + V(c);
  return {r.get(0), a * b + c};
}

}  // namespace qmaps
