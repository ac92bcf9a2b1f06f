#pragma once
// ops_test's two halves share this: core/ops.hpp's ops applied to arrays of inputs, lanes at a
// time, written once over the value type V. ops_test.cpp runs it at V = double (the scalar ops,
// compiled as the scalar path is), each ISA's unit (tests/ops_isa.cpp.in, compiled with that ISA's
// flags alone) at the ISA's batch. Only pointers cross between the two.
#include <array>
#include <bit>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "core/compiled_isas.hpp"
#include "core/ops.hpp"

namespace qmaps::testing::ops_lanes {

// The ops each of whose output lanes is a function of the same lane of the inputs.
enum class Op {
  fma, fms, neg, sqrt, abs, floor, split_mantissa, split_exponent, log, select, max, min, square,
  load_store, lanes_of, lanes_of_mask, negate, integer_lanes
};
inline constexpr const char* op_names[] = {
    "fma", "fms", "neg", "sqrt", "abs", "floor", "split_exponent_mantissa",
    "split_exponent_exponent", "log", "select", "max", "min", "square", "load_store", "lanes_of",
    "lanes_of_mask", "negate", "integer_lanes"};

template <class V>
V lanes_at(const double* p) {  // xsimd's own load: independent of ops::load
  if constexpr (std::floating_point<V>)
    return *p;
  else
    return V::load_unaligned(p);
}
template <class V>
void store_bits(std::uint64_t* out, V v) {
  std::array<double, ops::lanes<V>> x;
  if constexpr (std::floating_point<V>)
    x[0] = v;
  else
    v.store_unaligned(x.data());
  for (std::size_t l = 0; l < x.size(); ++l) out[l] = std::bit_cast<std::uint64_t>(x[l]);
}

// out[i] = the bits of op's result from a[i], b[i], c[i] and the mask m[i] != 0, for i < n (a
// multiple of the lanes).
template <class V>
void lane_op(Op op, std::size_t n, const double* a, const double* b, const double* c,
             const double* m, std::uint64_t* out) {
  constexpr std::size_t L = ops::lanes<V>;
  for (std::size_t i = 0; i < n; i += L) {
    const V x = lanes_at<V>(a + i), y = lanes_at<V>(b + i), z = lanes_at<V>(c + i);
    const ops::mask_t<V> mask = lanes_at<V>(m + i) != V(0.0);
    std::uint64_t* o = out + i;
    switch (op) {
      case Op::fma: store_bits(o, ops::fma(x, y, z)); break;
      case Op::fms: store_bits(o, ops::fms(x, y, z)); break;
      case Op::neg: store_bits(o, ops::neg(x)); break;
      case Op::sqrt: store_bits(o, ops::sqrt(x)); break;
      case Op::abs: store_bits(o, ops::abs(x)); break;
      case Op::floor: store_bits(o, ops::floor(x)); break;
      case Op::split_mantissa: {
        V e;
        store_bits(o, ops::split_exponent(x, e));
        break;
      }
      case Op::split_exponent: {
        V e;
        ops::split_exponent(x, e);
        store_bits(o, e);
        break;
      }
      case Op::log: store_bits(o, ops::log(x)); break;
      case Op::select: store_bits(o, ops::select(mask, x, y)); break;
      case Op::max: store_bits(o, ops::max(x, y)); break;
      case Op::min: store_bits(o, ops::min(x, y)); break;
      case Op::square: store_bits(o, ops::square(x)); break;
      case Op::load_store: {
        alignas(64) std::array<double, L> from, to;
        std::memcpy(from.data(), a + i, sizeof from);
        ops::store(to.data(), ops::load<V>(from.data()));
        for (std::size_t l = 0; l < L; ++l) o[l] = std::bit_cast<std::uint64_t>(to[l]);
        break;
      }
      case Op::lanes_of: {
        const auto v = ops::lanes_of(x);
        for (std::size_t l = 0; l < L; ++l) o[l] = std::bit_cast<std::uint64_t>(v[l]);
        break;
      }
      case Op::lanes_of_mask: {
        const auto v = ops::lanes_of(mask);
        for (std::size_t l = 0; l < L; ++l) o[l] = v[l];
        break;
      }
      case Op::negate: {
        const auto v = ops::lanes_of(ops::negate(mask));
        for (std::size_t l = 0; l < L; ++l) o[l] = v[l];
        break;
      }
      case Op::integer_lanes: {
        const auto v = ops::integer_lanes(x);
        for (std::size_t l = 0; l < L; ++l) o[l] = v[l];
        break;
      }
    }
  }
}

// The mask ops of one batch whose lane l is set where bit l of `pattern` is, and compress of v
// under it into `stored`, filled with `guard` first: a batch's room, then 8 it must not touch.
inline constexpr std::uint64_t guard = 0x7ff4'dead'beef'0001;
struct MaskOps {
  bool any, all;
  std::uint64_t bits;
  std::size_t count;
  std::array<double, 16> stored;
};
template <class V>
void mask_ops(std::uint64_t pattern, const double* v, MaskOps& out) {
  std::array<double, ops::lanes<V>> set;
  for (std::size_t l = 0; l < set.size(); ++l) set[l] = static_cast<double>(pattern >> l & 1);
  const auto m = lanes_at<V>(set.data()) != V(0.0);
  out.any = ops::any(m);
  out.all = ops::all(m);
  out.bits = ops::bits(m);
  out.stored.fill(std::bit_cast<double>(guard));
  out.count = ops::compress(out.stored.data(), m, lanes_at<V>(v));
}

template <class V>
void lane_index(double* out) {
  const auto v = ops::lanes_of(ops::lane_index<V>());
  std::memcpy(out, v.data(), sizeof v);
}

struct Path {
  const char* name;
  std::size_t lanes;
  void (*lane_op)(Op, std::size_t, const double*, const double*, const double*, const double*,
                  std::uint64_t*);
  void (*mask_ops)(std::uint64_t, const double*, MaskOps&);
  void (*lane_index)(double*);
};
template <class V>
Path path_of(const char* name) {
  return {name, ops::lanes<V>, &lane_op<V>, &mask_ops<V>, &lane_index<V>};
}

// The paths of an ISA's unit into out, their count: its architecture's; and where the unit's
// flags have AVX2, xsimd::avx2's (AVX2 without FMA), which takes core/ops.hpp's fallback.
template <class Arch, class NoForm = xsimd::avx2>
std::size_t paths_of(const char* isa, const char* fallback, Path* out) {
  out[0] = path_of<xsimd::batch<double, Arch>>(isa);
  if constexpr (std::is_base_of_v<NoForm, Arch>) {
    static_assert(ops::detail::form<NoForm> == ops::detail::Form::fallback);
    out[1] = path_of<xsimd::batch<double, NoForm>>(fallback);
    return 2;
  }
  return 1;
}
inline constexpr std::size_t max_paths = 2;

// Defined in each ISA's unit.
#define QMAPS_OPS_PATHS(name) std::size_t paths_##name(Path* out);
QMAPS_FOR_EACH_COMPILED_ISA(QMAPS_OPS_PATHS)
#undef QMAPS_OPS_PATHS

}  // namespace qmaps::testing::ops_lanes
