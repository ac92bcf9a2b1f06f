#pragma once
// The exact numbers the integrability tests (docs/integrability.md) evaluate a map over, each a
// value type its step takes as it takes a double:
//   Residue      an element of F_p, p a prime below 2^62 (FLINT's nmod arithmetic)
//   FunctionOfT  an element of F_p(t): numerator and denominator in FLINT's nmod_poly, divided by
//                their gcd after every operation, the denominator monic; its degree is the larger
//   Rational     an element of Q (GMP's mpq_class), always in lowest terms
// The prime is the thread's: a PrimeField in scope sets it. A number written as a double (a
// formula's number, a parameter, a kernel's coefficient) is the rational its shortest round-trip
// decimal denotes, the decimal one writes: 0.3 is 3/10, 2.5e-3 is 1/400. A division by zero raises
// DivisionByZero, which the tests count; a degree beyond the thread's cap raises DegreeCap.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include <flint/nmod_poly.h>
#include <flint/nmod_vec.h>
#include <gmpxx.h>

#include "core/ops.hpp"

namespace qmaps::exact {

struct DivisionByZero : std::domain_error {
  DivisionByZero() : std::domain_error("division by zero") {}
};
struct DegreeCap : std::length_error {
  explicit DegreeCap(long cap)
      : std::length_error("a degree beyond the cap of " + std::to_string(cap)) {}
};
struct HeightCap : std::length_error {
  explicit HeightCap(double bits)
      : std::length_error("a rational beyond the cap of " + std::to_string(static_cast<long>(bits)) +
                          " bits") {}
};

// The rational that the shortest decimal printing `x` exactly denotes (x finite).
mpq_class decimal_value(double x);

// The thread's prime field F_p while it is in scope (scopes nest), and the cap on the degrees of
// FunctionOfT's numerators and denominators.
class PrimeField {
 public:
  explicit PrimeField(std::uint64_t p, long degree_cap = 1L << 40);
  ~PrimeField();
  PrimeField(const PrimeField&) = delete;
  PrimeField& operator=(const PrimeField&) = delete;
  static const nmod_t& mod();
  static long degree_cap();
  static std::uint64_t reduce(const mpq_class& q);  // q mod p; DivisionByZero where p | den(q)

 private:
  nmod_t mod_;
  long cap_;
  const PrimeField* outer_;
};

// Whether n is prime (FLINT's n_is_prime: deterministic below 2^64).
bool is_prime(std::uint64_t n);

struct Residue {
  std::uint64_t v = 0;
  Residue() = default;
  explicit Residue(double x) : v(PrimeField::reduce(decimal_value(x))) {}
  static Residue of(std::uint64_t r) { Residue x; x.v = r; return x; }
  friend Residue operator+(Residue a, Residue b) { return of(nmod_add(a.v, b.v, PrimeField::mod())); }
  friend Residue operator-(Residue a, Residue b) { return of(nmod_sub(a.v, b.v, PrimeField::mod())); }
  friend Residue operator*(Residue a, Residue b) { return of(nmod_mul(a.v, b.v, PrimeField::mod())); }
  friend Residue operator/(Residue a, Residue b) {
    if (b.v == 0) throw DivisionByZero();
    return of(nmod_div(a.v, b.v, PrimeField::mod()));
  }
  friend bool operator==(Residue a, Residue b) { return a.v == b.v; }
};

class FunctionOfT {
 public:
  FunctionOfT();
  explicit FunctionOfT(double x);
  explicit FunctionOfT(Residue c);
  static FunctionOfT line(Residue at0, Residue slope);  // at0 + slope·t
  FunctionOfT(const FunctionOfT& o);
  FunctionOfT(FunctionOfT&& o) noexcept;
  FunctionOfT& operator=(FunctionOfT o) noexcept;
  ~FunctionOfT();

  long degree() const;  // max(deg numerator, deg denominator); 0 for a constant
  long numerator_degree() const { return nmod_poly_degree(num_); }
  long denominator_degree() const { return nmod_poly_degree(den_); }
  bool is_zero() const { return nmod_poly_is_zero(num_); }

  friend FunctionOfT operator+(const FunctionOfT& a, const FunctionOfT& b) { return combine(a, b, false); }
  friend FunctionOfT operator-(const FunctionOfT& a, const FunctionOfT& b) { return combine(a, b, true); }
  friend FunctionOfT operator*(const FunctionOfT& a, const FunctionOfT& b);
  friend FunctionOfT operator/(const FunctionOfT& a, const FunctionOfT& b);
  friend bool operator==(const FunctionOfT& a, const FunctionOfT& b);

 private:
  static FunctionOfT combine(const FunctionOfT& a, const FunctionOfT& b, bool subtract);
  static FunctionOfT product(const nmod_poly_t n1, const nmod_poly_t n2, const nmod_poly_t d1,
                             const nmod_poly_t d2);
  void normalize();  // gcd out, denominator monic, degrees capped
  nmod_poly_t num_, den_;
};

// The thread's cap on the size of Rational's operands while in scope (scopes nest): an operation
// whose operands' numerators and denominators have more bits together raises HeightCap, before
// GMP is asked for the memory.
class HeightLimit {
 public:
  explicit HeightLimit(double bits);
  ~HeightLimit();
  HeightLimit(const HeightLimit&) = delete;
  HeightLimit& operator=(const HeightLimit&) = delete;
  static void check(const mpq_class& a, const mpq_class& b);

 private:
  double outer_bits_;
  const HeightLimit* outer_;
};

struct Rational {
  mpq_class v;
  Rational() = default;
  explicit Rational(double x) : v(decimal_value(x)) {}
  explicit Rational(mpq_class q) : v(std::move(q)) {}
  friend Rational operator+(const Rational& a, const Rational& b) {
    HeightLimit::check(a.v, b.v);
    return Rational(mpq_class(a.v + b.v));
  }
  friend Rational operator-(const Rational& a, const Rational& b) {
    HeightLimit::check(a.v, b.v);
    return Rational(mpq_class(a.v - b.v));
  }
  friend Rational operator*(const Rational& a, const Rational& b) {
    HeightLimit::check(a.v, b.v);
    return Rational(mpq_class(a.v * b.v));
  }
  friend Rational operator/(const Rational& a, const Rational& b) {
    if (sgn(b.v) == 0) throw DivisionByZero();
    HeightLimit::check(a.v, b.v);
    return Rational(mpq_class(a.v / b.v));
  }
  friend bool operator==(const Rational& a, const Rational& b) { return a.v == b.v; }
  // log of the height max(|numerator|, |denominator|)
  double log_height() const;
};

template <class V>
concept Number = std::same_as<V, Residue> || std::same_as<V, FunctionOfT> || std::same_as<V, Rational>;

}  // namespace qmaps::exact

// A kernel's fused operations, exactly: over a field a·b + c has nothing to round.
namespace qmaps::ops {
template <exact::Number V>
inline V fma(const V& a, const V& b, const V& c) { return a * b + c; }
template <exact::Number V>
inline V fms(const V& a, const V& b, const V& c) { return a * b - c; }
}  // namespace qmaps::ops
