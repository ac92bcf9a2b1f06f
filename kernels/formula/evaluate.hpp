#pragma once
// A formula program (program.hpp) run over any value type V with the project's ops, one
// algorithm for every path: double (the reference and the lowering's constants), every SIMD
// batch, duals over both. The register file holds `lanes` values of V per register (a block's
// chains): each instruction is decoded once and applied to all of them, so that its dispatch is
// shared by lanes × W orbits.
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/ops.hpp"
#include "core/ops_exp.hpp"
#include "kernels/formula/program.hpp"

namespace qmaps::formula {

// sin and cos where ops::sin_cos holds them (|x| ≤ 2^20), NaN beyond: the orbit's escape.
template <class V>
inline void sin_cos_within(V x, V& sine, V& cosine) {
  ops::sin_cos(x, sine, cosine);
  const auto beyond = ops::negate(ops::abs(x) <= V(0x1p20));
  sine = ops::select(beyond, V(std::numeric_limits<double>::quiet_NaN()), sine);
  cosine = ops::select(beyond, V(std::numeric_limits<double>::quiet_NaN()), cosine);
}

template <class V>
inline V apply(Code code, V a, V b, V c) {
  switch (code) {
    case Code::add: return a + b;
    case Code::sub: return a - b;
    case Code::mul: return a * b;
    case Code::div: return a / b;
    case Code::neg: return ops::neg(a);
    case Code::fma: return ops::fma(a, b, c);
    case Code::sqrt: return ops::sqrt(a);
    case Code::sin: {
      V s, co;
      sin_cos_within(a, s, co);
      return s;
    }
    case Code::cos: {
      V s, co;
      sin_cos_within(a, s, co);
      return co;
    }
    case Code::exp: return ops::exp(a);
    case Code::log: return ops::log(a);
  }
  return a;
}

// Runs the program on registers r[register · lanes + l], l < lanes: the inputs set, the constants
// loaded (load_constants), the rest written here.
template <class V>
inline void load_constants(const Program& p, V* r, std::size_t lanes) {
  for (std::size_t k = 0; k < p.constants.size(); ++k)
    for (std::size_t l = 0; l < lanes; ++l) r[(p.inputs + k) * lanes + l] = V(p.constants[k]);
}

template <class V, std::size_t lanes>
inline void run(const Program& p, V* r) {
  for (const Instruction& i : p.code) {
    V* out = r + i.out * lanes;
    const V* a = r + i.a * lanes;
    const V* b = r + i.b * lanes;
    const V* c = r + i.c * lanes;
    const auto each = [&](auto f) {  // the case's own loop over the lanes
      for (std::size_t l = 0; l < lanes; ++l) out[l] = f(a[l], b[l], c[l]);
    };
    switch (i.code) {
      case Code::add: each([](V x, V y, V) { return x + y; }); break;
      case Code::sub: each([](V x, V y, V) { return x - y; }); break;
      case Code::mul: each([](V x, V y, V) { return x * y; }); break;
      case Code::div: each([](V x, V y, V) { return x / y; }); break;
      case Code::neg: each([](V x, V, V) { return ops::neg(x); }); break;
      case Code::fma: each([](V x, V y, V z) { return ops::fma(x, y, z); }); break;
      case Code::sqrt: each([](V x, V, V) { return ops::sqrt(x); }); break;
      case Code::sin: each([](V x, V, V) { return apply(Code::sin, x, x, x); }); break;
      case Code::cos: each([](V x, V, V) { return apply(Code::cos, x, x, x); }); break;
      case Code::exp: each([](V x, V, V) { return ops::exp(x); }); break;
      case Code::log: each([](V x, V, V) { return ops::log(x); }); break;
    }
  }
}

// This thread's registers for program p at V, `lanes` values per register, with its constants
// loaded the first time. Eight files, by the program's id: the programs of one map (made one after
// another) keep theirs while a run alternates between them (the step, then its samples').
template <class V, std::size_t lanes = 1>
inline V* registers_for(const Program& p) {
  struct File {
    std::uint64_t loaded = 0;
    std::vector<V> r;
  };
  thread_local std::array<File, 8> files;
  File& file = files[p.id % files.size()];
  if (file.loaded != p.id) [[unlikely]] {
    file.r.resize(p.registers() * lanes);
    load_constants(p, file.r.data(), lanes);
    file.loaded = p.id;
  }
  return file.r.data();
}

}  // namespace qmaps::formula
