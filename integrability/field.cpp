#include "integrability/field.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include <flint/ulong_extras.h>

namespace qmaps::exact {
namespace {
thread_local const PrimeField* current = nullptr;

const PrimeField& field() {
  if (!current) throw std::logic_error("exact arithmetic mod p outside a PrimeField");
  return *current;
}

// The monic denominator 1 of a new function.
void set_one(nmod_poly_t p) { nmod_poly_one(p); }
// The rational with the smallest denominator in [lo, hi], 0 <= lo < hi (by continued fractions).
mpq_class simplest_between(const mpq_class& lo, const mpq_class& hi) {
  mpz_class whole;
  mpz_fdiv_q(whole.get_mpz_t(), lo.get_num_mpz_t(), lo.get_den_mpz_t());
  if (mpq_class(whole) == lo) return lo;
  if (mpq_class(whole + 1) <= hi) return mpq_class(whole + 1);
  const mpq_class rest = simplest_between(1 / (hi - whole), 1 / (lo - whole));
  return mpq_class(whole + 1 / rest);
}

}  // namespace

mpq_class decimal_value(double x) {
  if (!std::isfinite(x)) throw std::domain_error("a number that is not finite has no exact value");
  char text[64];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, x);
  std::string_view s(text, static_cast<std::size_t>(end - text));
  bool negative = false;
  if (!s.empty() && s.front() == '-') negative = true, s.remove_prefix(1);
  long exponent = 0;
  if (const auto e = s.find_first_of("eE"); e != std::string_view::npos) {
    std::from_chars(s.data() + e + 1 + (s[e + 1] == '+'), s.data() + s.size(), exponent);
    s = s.substr(0, e);
  }
  std::string digits;
  for (const char c : s) {
    if (c == '.') continue;
    digits += c;
  }
  if (const auto dot = s.find('.'); dot != std::string_view::npos)
    exponent -= static_cast<long>(s.size() - dot - 1);
  const auto significant = digits.size() - std::min(digits.find_first_not_of('0'), digits.size());
  if (significant > 15) {  // no decimal one writes: a value rounded to a double
    const double below = std::nextafter(std::fabs(x), 0.0), above = std::nextafter(std::fabs(x), 1e308);
    const mpq_class at(std::fabs(x));
    const mpq_class q = simplest_between((at + mpq_class(below)) / 2, (at + mpq_class(above)) / 2);
    return negative ? mpq_class(-q) : q;
  }
  mpz_class m(digits, 10), scale;
  mpz_ui_pow_ui(scale.get_mpz_t(), 10, static_cast<unsigned long>(std::labs(exponent)));
  mpq_class q = exponent >= 0 ? mpq_class(m * scale) : mpq_class(m, scale);
  q.canonicalize();
  return negative ? mpq_class(-q) : q;
}

PrimeField::PrimeField(std::uint64_t p, long degree_cap) : cap_(degree_cap), outer_(current) {
  nmod_init(&mod_, p);
  current = this;
}
PrimeField::~PrimeField() { current = outer_; }
const nmod_t& PrimeField::mod() { return field().mod_; }
long PrimeField::degree_cap() { return field().cap_; }

std::uint64_t PrimeField::reduce(const mpq_class& q) {
  const nmod_t& m = mod();
  const std::uint64_t num = mpz_fdiv_ui(q.get_num_mpz_t(), m.n);
  const std::uint64_t den = mpz_fdiv_ui(q.get_den_mpz_t(), m.n);
  if (den == 0) throw DivisionByZero();
  return nmod_div(num, den, m);
}

bool is_prime(std::uint64_t n) { return n >= 2 && n_is_prime(n); }

// ---- F_p(t) -------------------------------------------------------------------------------

FunctionOfT::FunctionOfT() {
  nmod_poly_init_preinv(num_, PrimeField::mod().n, PrimeField::mod().ninv);
  nmod_poly_init_preinv(den_, PrimeField::mod().n, PrimeField::mod().ninv);
  set_one(den_);
}
FunctionOfT::FunctionOfT(Residue c) : FunctionOfT() { nmod_poly_set_coeff_ui(num_, 0, c.v); }
FunctionOfT::FunctionOfT(double x) : FunctionOfT(Residue(x)) {}
FunctionOfT FunctionOfT::line(Residue at0, Residue slope) {
  FunctionOfT f(at0);
  nmod_poly_set_coeff_ui(f.num_, 1, slope.v);
  return f;
}
FunctionOfT::FunctionOfT(const FunctionOfT& o) {
  nmod_poly_init_preinv(num_, o.num_->mod.n, o.num_->mod.ninv);
  nmod_poly_init_preinv(den_, o.num_->mod.n, o.num_->mod.ninv);
  nmod_poly_set(num_, o.num_);
  nmod_poly_set(den_, o.den_);
}
FunctionOfT::FunctionOfT(FunctionOfT&& o) noexcept {
  nmod_poly_init_preinv(num_, o.num_->mod.n, o.num_->mod.ninv);
  nmod_poly_init_preinv(den_, o.num_->mod.n, o.num_->mod.ninv);
  set_one(den_);
  std::swap(num_[0], o.num_[0]);  // the whole struct: nmod_poly_swap keeps each one's modulus
  std::swap(den_[0], o.den_[0]);
}
FunctionOfT& FunctionOfT::operator=(FunctionOfT o) noexcept {
  std::swap(num_[0], o.num_[0]);
  std::swap(den_[0], o.den_[0]);
  return *this;
}
FunctionOfT::~FunctionOfT() {
  nmod_poly_clear(num_);
  nmod_poly_clear(den_);
}

long FunctionOfT::degree() const {
  return std::max<long>({nmod_poly_degree(num_), nmod_poly_degree(den_), 0});
}

void FunctionOfT::normalize() {
  const long cap = PrimeField::degree_cap();
  if (nmod_poly_degree(num_) > cap || nmod_poly_degree(den_) > cap) throw DegreeCap(cap);
  if (nmod_poly_is_zero(num_)) {
    set_one(den_);
    return;
  }
  if (nmod_poly_degree(den_) > 0) {
    nmod_poly_t g;
    nmod_poly_init_mod(g, num_->mod);
    nmod_poly_gcd(g, num_, den_);
    if (nmod_poly_degree(g) > 0) {
      nmod_poly_div(num_, num_, g);
      nmod_poly_div(den_, den_, g);
    }
    nmod_poly_clear(g);
  }
  const mp_limb_t lead = nmod_poly_lead(den_)[0];
  if (lead != 1) {
    const mp_limb_t inverse = n_invmod(lead, den_->mod.n);
    nmod_poly_scalar_mul_nmod(num_, num_, inverse);
    nmod_poly_scalar_mul_nmod(den_, den_, inverse);
  }
}

FunctionOfT FunctionOfT::combine(const FunctionOfT& a, const FunctionOfT& b, bool subtract) {
  FunctionOfT r;
  const auto add = subtract ? nmod_poly_sub : nmod_poly_add;
  if (nmod_poly_equal(a.den_, b.den_)) {  // polynomials, and a common denominator
    add(r.num_, a.num_, b.num_);
    nmod_poly_set(r.den_, a.den_);
  } else {
    nmod_poly_t x, y;
    nmod_poly_init_mod(x, a.num_->mod);
    nmod_poly_init_mod(y, a.num_->mod);
    nmod_poly_mul(x, a.num_, b.den_);
    nmod_poly_mul(y, b.num_, a.den_);
    add(r.num_, x, y);
    nmod_poly_mul(r.den_, a.den_, b.den_);
    nmod_poly_clear(x);
    nmod_poly_clear(y);
  }
  r.normalize();
  return r;
}

// (n1 n2)/(d1 d2), reduced: the product and, crosswise, the quotient.
FunctionOfT FunctionOfT::product(const nmod_poly_t n1, const nmod_poly_t n2, const nmod_poly_t d1,
                                 const nmod_poly_t d2) {
  const long cap = PrimeField::degree_cap();
  if (nmod_poly_degree(n1) + nmod_poly_degree(n2) > cap ||
      nmod_poly_degree(d1) + nmod_poly_degree(d2) > cap)
    throw DegreeCap(cap);
  FunctionOfT r;
  nmod_poly_mul(r.num_, n1, n2);
  nmod_poly_mul(r.den_, d1, d2);
  r.normalize();
  return r;
}

FunctionOfT operator*(const FunctionOfT& a, const FunctionOfT& b) {
  return FunctionOfT::product(a.num_, b.num_, a.den_, b.den_);
}

FunctionOfT operator/(const FunctionOfT& a, const FunctionOfT& b) {
  if (b.is_zero()) throw DivisionByZero();
  return FunctionOfT::product(a.num_, b.den_, a.den_, b.num_);
}

bool operator==(const FunctionOfT& a, const FunctionOfT& b) {
  return nmod_poly_equal(a.num_, b.num_) && nmod_poly_equal(a.den_, b.den_);
}

// ---- Q --------------------------------------------------------------------------------------

namespace {
thread_local const HeightLimit* height_limit = nullptr;
thread_local double height_bits = 0;

double bits(const mpq_class& q) {
  return static_cast<double>(mpz_sizeinbase(q.get_num_mpz_t(), 2) + mpz_sizeinbase(q.get_den_mpz_t(), 2));
}
}  // namespace

HeightLimit::HeightLimit(double bits) : outer_bits_(height_bits), outer_(height_limit) {
  height_limit = this;
  height_bits = bits;
}
HeightLimit::~HeightLimit() {
  height_limit = outer_;
  height_bits = outer_bits_;
}
void HeightLimit::check(const mpq_class& a, const mpq_class& b) {
  if (height_limit && bits(a) + bits(b) > height_bits) throw HeightCap(height_bits);
}

double Rational::log_height() const {
  const auto log_abs = [](const mpz_class& z) {
    if (sgn(z) == 0) return 0.0;
    long e = 0;
    const double m = mpz_get_d_2exp(&e, z.get_mpz_t());
    return std::log(std::fabs(m)) + static_cast<double>(e) * std::log(2.0);
  };
  return std::max(log_abs(v.get_num()), log_abs(v.get_den()));
}

}  // namespace qmaps::exact
