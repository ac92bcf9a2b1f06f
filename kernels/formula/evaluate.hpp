#pragma once
// A formula program (program.hpp) run over any value type V with the project's ops, one
// algorithm for every path: double (the reference and the lowering's constants), every SIMD
// batch, duals over both. The register file holds `lanes` values of V per register (a block's
// chains): each instruction is decoded once and applied to all of them, so that its dispatch is
// shared by lanes × W orbits. The previous instruction's results stay in the processor's
// registers for the operands chained to it (program.hpp), and a result nothing else reads is not
// written: stores, 1 per instruction and chain otherwise, bound the evaluation.
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
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

// One operation of the program (a, then b, then c, as it reads them).
template <Code code, class V>
[[gnu::always_inline]] inline V compute(V a, V b, V c) {
  if constexpr (code == Code::add) return a + b;
  else if constexpr (code == Code::sub) return a - b;
  else if constexpr (code == Code::mul) return a * b;
  else if constexpr (code == Code::div) return a / b;
  else if constexpr (code == Code::neg) return ops::neg(a);
  else if constexpr (code == Code::fma) return ops::fma(a, b, c);
  else if constexpr (code == Code::fms) return ops::fms(a, b, c);
  else if constexpr (code == Code::sqrt) return ops::sqrt(a);
  else if constexpr (code == Code::exp) return ops::exp(a);
  else if constexpr (code == Code::log) return ops::log(a);
  else {
    V sine, cosine;
    sin_cos_within(a, sine, cosine);
    return code == Code::sin ? sine : cosine;
  }
}

template <class V>
inline V apply(Code code, V a, V b, V c) {
  switch (code) {
    case Code::add: return compute<Code::add>(a, b, c);
    case Code::sub: return compute<Code::sub>(a, b, c);
    case Code::mul: return compute<Code::mul>(a, b, c);
    case Code::div: return compute<Code::div>(a, b, c);
    case Code::neg: return compute<Code::neg>(a, b, c);
    case Code::fma: return compute<Code::fma>(a, b, c);
    case Code::fms: return compute<Code::fms>(a, b, c);
    case Code::sqrt: return compute<Code::sqrt>(a, b, c);
    case Code::sin: return compute<Code::sin>(a, b, c);
    case Code::cos: return compute<Code::cos>(a, b, c);
    case Code::exp: return compute<Code::exp>(a, b, c);
    case Code::log: return compute<Code::log>(a, b, c);
  }
  return a;
}

// The constants into registers r[register · lanes + l], l < lanes.
template <class V>
inline void load_constants(const Program& p, V* r, std::size_t lanes) {
  for (std::size_t k = 0; k < p.constants.size(); ++k)
    for (std::size_t l = 0; l < lanes; ++l) r[(p.inputs + k) * lanes + l] = V(p.constants[k]);
}

namespace detail {

// Instruction i of arithmetic `code` over the lanes, its chained operands from `previous` (the
// last instruction's results), its results into `previous` and, where stored, its register.
template <Code code, Chained chained, bool stored, class V, std::size_t lanes>
[[gnu::always_inline]] inline void execute(const Instruction& i, V* r, V (&previous)[lanes]) {
  V* out = r + i.out * lanes;
  const V* a = r + i.a * lanes;
  const V* b = r + i.b * lanes;
  const V* c = r + i.c * lanes;
#pragma GCC unroll 16
  for (std::size_t l = 0; l < lanes; ++l) {
    const V x = chained == Chained::a || chained == Chained::a_and_b ? previous[l] : a[l];
    const V y = chained == Chained::b || chained == Chained::a_and_b ? previous[l] : b[l];
    const V z = chained == Chained::c ? previous[l] : c[l];
    previous[l] = compute<code>(x, y, z);
    if constexpr (stored) out[l] = previous[l];
  }
}

// A function, from and to the registers (never chained), out of line: a call inside the
// program's loop would make the compiler keep `previous` in memory.
template <Code code, std::size_t lanes, class V>
[[gnu::noinline]] void each(const Instruction& i, V* r) {
  for (std::size_t l = 0; l < lanes; ++l)
    r[i.out * lanes + l] = compute<code>(r[i.a * lanes + l], V(0.0), V(0.0));
}

// An instruction's kind: its code, its chained operands and whether it is stored.
constexpr int kinds = (static_cast<int>(Code::log) + 1) * 10;
inline int kind_of(const Instruction& i) {
  return static_cast<int>(i.code) * 10 + static_cast<int>(i.chained) * 2 + i.stored;
}
template <int kind, class V, std::size_t lanes>
[[gnu::always_inline]] inline void execute_kind(const Instruction& i, V* r, V (&previous)[lanes]) {
  constexpr Code code = static_cast<Code>(kind / 10);
  if constexpr (chainable(code))
    execute<code, static_cast<Chained>(kind % 10 / 2), kind % 2 == 1>(i, r, previous);
  else if constexpr (kind % 10 == 1)  // (unchained, stored: the only kind of a function)
    each<code, lanes>(i, r);
}
// The instruction run by its kind's code: one jump through a table of them all, every kind
// inlined in one loop, so that `previous` stays in the processor's registers.
template <class V, std::size_t lanes, int... kind>
[[gnu::always_inline]] inline void dispatch(const Instruction& i, V* r, V (&previous)[lanes],
                                            std::integer_sequence<int, kind...>) {
  const int k = kind_of(i);
  (void)((k == kind && (execute_kind<kind>(i, r, previous), true)) || ...);
}

}  // namespace detail

// Runs the program on registers r[register · lanes + l], l < lanes: the inputs set, the constants
// loaded (load_constants), the rest written here.
template <class V, std::size_t lanes>
inline void run(const Program& p, V* r) {
  V previous[lanes] = {};  // (each set before it is read)
  for (const Instruction& i : p.code)
    detail::dispatch(i, r, previous, std::make_integer_sequence<int, detail::kinds>{});
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
