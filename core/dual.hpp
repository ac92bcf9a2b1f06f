#pragma once
// Forward-mode differentiation: a value and its derivatives along N directions,
//
//   x = (v, d₁ … d_N),  (a ∘ b).d = rule of ∘,  e.g.  (a·b).d = a.d·b.v + a.v·b.d.
//
// A kernel's step run on State<Dual<V, N>> advances the state and N deviation vectors together:
// the tangent map comes from the map's own code, not from a second hand-written Jacobian. Every
// rule goes through core/ops, one rounding per operation in a fixed order, so the derivatives,
// like the values, are the same bits on the scalar path and in every lane of every ISA. The
// values are exactly those of the plain step: a value never reads a derivative.
//
// Comparisons and masks read the values only; floor's derivative is 0 and abs's is sign·d;
// exp, log, sin and cos (the formulas' functions) differentiate as written beside each.
// Calls are qualified (ops::neg, not neg): unqualified, argument-dependent lookup would find
// xsimd's own neg, whose AVX-512 form is 0 − a (+0 → +0).
#include <array>
#include <cstddef>
#include <type_traits>

#include "core/ops.hpp"
#include "core/ops_exp.hpp"

namespace qmaps {

template <class V, std::size_t N>
struct Dual {
  V v;
  std::array<V, N> d;

  Dual() = default;
  explicit Dual(double constant) : v(constant) { d.fill(V(0.0)); }
  Dual(V value, const std::array<V, N>& derivatives) : v(value), d(derivatives) {}

  friend Dual operator+(const Dual& a, const Dual& b) {
    Dual r;
    r.v = a.v + b.v;
    for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] + b.d[i];
    return r;
  }
  friend Dual operator-(const Dual& a, const Dual& b) {
    Dual r;
    r.v = a.v - b.v;
    for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] - b.d[i];
    return r;
  }
  friend Dual operator*(const Dual& a, const Dual& b) {  // a.d·b.v + a.v·b.d
    Dual r;
    r.v = a.v * b.v;
    for (std::size_t i = 0; i < N; ++i) r.d[i] = ops::fma(a.d[i], b.v, a.v * b.d[i]);
    return r;
  }
  friend Dual operator/(const Dual& a, const Dual& b) {  // (a.d − q·b.d)·(1/b.v), q = a.v/b.v
    Dual r;
    r.v = a.v / b.v;
    const V inverse = V(1.0) / b.v;  // one division for every direction
    for (std::size_t i = 0; i < N; ++i) r.d[i] = ops::neg(ops::fms(r.v, b.d[i], a.d[i])) * inverse;
    return r;
  }
  friend auto operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
  friend auto operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
  friend auto operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
  friend auto operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }
  friend auto operator==(const Dual& a, const Dual& b) { return a.v == b.v; }
  friend auto operator!=(const Dual& a, const Dual& b) { return a.v != b.v; }
};

template <class T>
inline constexpr bool is_dual = false;
template <class V, std::size_t N>
inline constexpr bool is_dual<Dual<V, N>> = true;

namespace ops {

template <class V, std::size_t N>
struct traits<Dual<V, N>> {
  using scalar = typename traits<V>::scalar;
  using mask = typename traits<V>::mask;
  static constexpr std::size_t lanes = traits<V>::lanes;
};

template <class V, std::size_t N>
inline Dual<V, N> fma(const Dual<V, N>& a, const Dual<V, N>& b, const Dual<V, N>& c) {
  Dual<V, N> r;  // value a·b + c rounded once; derivative a.d·b.v + (a.v·b.d + c.d)
  r.v = ops::fma(a.v, b.v, c.v);
  for (std::size_t i = 0; i < N; ++i) r.d[i] = ops::fma(a.d[i], b.v, ops::fma(a.v, b.d[i], c.d[i]));
  return r;
}
template <class V, std::size_t N>
inline Dual<V, N> fms(const Dual<V, N>& a, const Dual<V, N>& b, const Dual<V, N>& c) {
  Dual<V, N> r;  // value a·b − c rounded once; derivative a.d·b.v + (a.v·b.d − c.d)
  r.v = ops::fms(a.v, b.v, c.v);
  for (std::size_t i = 0; i < N; ++i) r.d[i] = ops::fma(a.d[i], b.v, ops::fms(a.v, b.d[i], c.d[i]));
  return r;
}
template <class V, std::size_t N>
inline Dual<V, N> sqrt(const Dual<V, N>& a) {  // d·(1/(2√v))
  Dual<V, N> r;
  r.v = ops::sqrt(a.v);
  const V inverse = V(1.0) / (r.v + r.v);
  for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] * inverse;
  return r;
}
template <class V, std::size_t N>
inline Dual<V, N> exp(const Dual<V, N>& a) {  // d·e^v
  Dual<V, N> r;
  r.v = ops::exp(a.v);
  for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] * r.v;
  return r;
}
template <class V, std::size_t N>
inline Dual<V, N> log(const Dual<V, N>& a) {  // d/v
  Dual<V, N> r;
  r.v = ops::log(a.v);
  for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] / a.v;
  return r;
}
template <class V, std::size_t N>
inline void sin_cos(const Dual<V, N>& a, Dual<V, N>& sine, Dual<V, N>& cosine) {
  V s, c;  // (sin, cos)′ = (cos, −sin)·d
  ops::sin_cos(a.v, s, c);
  sine.v = s;
  cosine.v = c;
  for (std::size_t i = 0; i < N; ++i) {
    sine.d[i] = a.d[i] * c;
    cosine.d[i] = ops::neg(a.d[i] * s);
  }
}
template <class V, std::size_t N>
inline Dual<V, N> select(mask_t<V> m, const Dual<V, N>& a, const Dual<V, N>& b) {
  Dual<V, N> r;
  r.v = ops::select(m, a.v, b.v);
  for (std::size_t i = 0; i < N; ++i) r.d[i] = ops::select(m, a.d[i], b.d[i]);
  return r;
}
template <class V, std::size_t N>
inline Dual<V, N> neg(const Dual<V, N>& a) {
  Dual<V, N> r;
  r.v = ops::neg(a.v);
  for (std::size_t i = 0; i < N; ++i) r.d[i] = ops::neg(a.d[i]);
  return r;
}
template <class V, std::size_t N>
inline Dual<V, N> abs(const Dual<V, N>& a) {
  return ops::select(a.v < V(0.0), ops::neg(a), a);
}
template <class V, std::size_t N>
inline Dual<V, N> floor(const Dual<V, N>& a) {
  return Dual<V, N>(ops::floor(a.v), {});
}
template <class V, std::size_t N>  // max(a, b) = b > a ? b : a, as for V
inline Dual<V, N> max(const Dual<V, N>& a, const Dual<V, N>& b) {
  return ops::select(b.v > a.v, b, a);
}
template <class V, std::size_t N>
inline Dual<V, N> min(const Dual<V, N>& a, const Dual<V, N>& b) {
  return ops::select(b.v < a.v, b, a);
}

}  // namespace ops

// The state s with its derivatives along N deviation vectors w[j] (each a state of V): the
// tangent map's input. value_of / derivatives_of take them apart again.
template <std::size_t N, class V, std::size_t S>
std::array<Dual<V, N>, S> with_deviations(const std::array<V, S>& s,
                                          const std::array<std::array<V, S>, N>& w) {
  std::array<Dual<V, N>, S> x;
  for (std::size_t k = 0; k < S; ++k) {
    x[k].v = s[k];
    for (std::size_t j = 0; j < N; ++j) x[k].d[j] = w[j][k];
  }
  return x;
}
template <std::size_t N, class V, std::size_t S>
void split(const std::array<Dual<V, N>, S>& x, std::array<V, S>& s,
           std::array<std::array<V, S>, N>& w) {
  for (std::size_t k = 0; k < S; ++k) {
    s[k] = x[k].v;
    for (std::size_t j = 0; j < N; ++j) w[j][k] = x[k].d[j];
  }
}

}  // namespace qmaps
