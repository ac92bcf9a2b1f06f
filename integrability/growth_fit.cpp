#include "integrability/growth_fit.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <flint/fmpz_poly.h>
#include <flint/fmpz_poly_factor.h>
#include <gmpxx.h>

namespace qmaps::exact {
namespace {

using Poly = std::vector<mpq_class>;  // coefficients, lowest first

// Berlekamp–Massey over Q: the connection polynomial C (C_0 = 1) of the shortest recurrence
// Σ_{i=0}^{L} C_i s_{n−i} = 0 that the whole of s satisfies, and L.
Poly berlekamp_massey(const std::vector<mpq_class>& s, std::size_t& L) {
  Poly C = {1}, B = {1};
  L = 0;
  std::size_t m = 1;
  mpq_class b = 1;
  for (std::size_t n = 0; n < s.size(); ++n) {
    mpq_class d = s[n];
    for (std::size_t i = 1; i <= L && i < C.size(); ++i) d += C[i] * s[n - i];
    if (d == 0) {
      ++m;
      continue;
    }
    const Poly T = C;
    const mpq_class f = d / b;
    if (C.size() < B.size() + m) C.resize(B.size() + m, 0);
    for (std::size_t i = 0; i < B.size(); ++i) C[i + m] -= f * B[i];
    if (2 * L <= n) {
      L = n + 1 - L;
      B = T;
      b = d;
      m = 1;
    } else {
      ++m;
    }
  }
  C.resize(L + 1, 0);
  return C;
}

std::string term(const mpq_class& c, std::size_t power, const char* x, bool first) {
  std::ostringstream out;
  const bool negative = sgn(c) < 0;
  const mpq_class a = abs(c);
  out << (negative ? (first ? "-" : " - ") : (first ? "" : " + "));
  if (a != 1 || power == 0) out << a.get_str() << (power ? "*" : "");
  if (power) out << x << (power > 1 ? "^" + std::to_string(power) : "");
  return out.str();
}

std::string poly_text(const Poly& p, const char* x) {
  std::string s;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p[i] != 0) s += term(p[i], i, x, s.empty());
  return s.empty() ? "0" : s;
}

// The moduli of the roots of an integer polynomial (Eigen: the companion matrix's eigenvalues).
std::vector<double> root_moduli(const fmpz_poly_t p) {
  const long n = fmpz_poly_degree(p);
  std::vector<double> out;
  if (n < 1) return out;
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
  const double lead = fmpz_get_d(fmpz_poly_get_coeff_ptr(p, n));
  for (long i = 0; i < n; ++i) {
    const fmpz* c = fmpz_poly_get_coeff_ptr(p, i);
    companion(0, n - 1 - i) = -(c ? fmpz_get_d(c) : 0.0) / lead;
  }
  for (long i = 1; i < n; ++i) companion(i, i - 1) = 1;
  Eigen::EigenSolver<Eigen::MatrixXd> solver(companion, false);
  for (const auto& r : solver.eigenvalues()) out.push_back(std::abs(r));
  return out;
}

Growth from_recurrence(const std::vector<mpq_class>& s, const Poly& C, std::size_t L) {
  Growth g;
  g.recurrence = true;
  for (std::size_t i = 1; i <= L; ++i) g.coefficients.push_back(mpq_class(-C[i]).get_str());
  // P(z) = (Q(z) Σ s_n z^n) mod z^L, Q = C
  Poly P(L, 0);
  for (std::size_t k = 0; k < L; ++k)
    for (std::size_t i = 0; i <= k; ++i) P[k] += C[i] * s[k - i];
  g.generating_function = "(" + poly_text(P, "z") + ")/(" + poly_text(C, "z") + ")";

  // χ(x) = Σ C_i x^{L−i}, over Z
  mpz_class denominators = 1;
  for (const auto& c : C) mpz_lcm(denominators.get_mpz_t(), denominators.get_mpz_t(), c.get_den_mpz_t());
  fmpz_poly_t chi;
  fmpz_poly_init(chi);
  for (std::size_t i = 0; i <= L; ++i) {
    const mpz_class v = mpz_class(C[i] * denominators);
    fmpz_t f;
    fmpz_init(f);
    fmpz_set_mpz(f, v.get_mpz_t());
    fmpz_poly_set_coeff_fmpz(chi, static_cast<slong>(L - i), f);
    fmpz_clear(f);
  }
  fmpz_poly_factor_t factors;
  fmpz_poly_factor_init(factors);
  fmpz_poly_factor(factors, chi);
  long cyclotomic_multiplicity = 0;
  double lambda = 0;
  std::string text;
  for (slong k = 0; k < factors->num; ++k) {
    char* f = fmpz_poly_get_str_pretty(factors->p + k, "x");
    text += (text.empty() ? "" : "*") + std::string("(") + f + ")" +
            (factors->exp[k] > 1 ? "^" + std::to_string(factors->exp[k]) : "");
    flint_free(f);
    if (fmpz_poly_is_cyclotomic(factors->p + k)) {
      cyclotomic_multiplicity = std::max<long>(cyclotomic_multiplicity, factors->exp[k]);
      lambda = std::max(lambda, 1.0);
    } else {
      for (const double r : root_moduli(factors->p + k)) lambda = std::max(lambda, r);
    }
  }
  g.characteristic = text.empty() ? "1" : text;
  fmpz_poly_factor_clear(factors);
  fmpz_poly_clear(chi);
  if (lambda > 1 + 1e-9) {
    g.kind = Growth::Kind::exponential;
    g.lambda = lambda;
    g.entropy = std::log(lambda);
    g.entropy_error = 1e-12 * std::max(1.0, g.entropy);
    g.reason = "a generating function fits, and its characteristic polynomial has a root of "
               "modulus " + std::to_string(lambda) + " > 1";
  } else {
    g.kind = Growth::Kind::polynomial;
    g.degree = static_cast<double>(std::max<long>(cyclotomic_multiplicity - 1, 0));
    g.reason = "a generating function fits, with every root of its characteristic polynomial on "
               "the unit circle or inside it; the largest multiplicity of a root of unity is " +
               std::to_string(cyclotomic_multiplicity);
  }
  return g;
}

Growth from_tail(const std::vector<double>& d) {
  Growth g;
  std::vector<double> logs;  // log d_{n+1}/d_n over the last (up to) three steps
  const std::size_t N = d.size();
  for (std::size_t n = N >= 4 ? N - 4 : 0; n + 1 < N; ++n)
    if (d[n] > 0 && d[n + 1] > 0) logs.push_back(std::log(d[n + 1] / d[n]));
  if (N < 3 || logs.empty()) {
    g.reason = "too few terms (" + std::to_string(N) + ") to judge the growth";
    return g;
  }
  const auto [low, high] = std::minmax_element(logs.begin(), logs.end());
  double mean = 0;
  for (const double l : logs) mean += l;
  mean /= static_cast<double>(logs.size());
  const double n = static_cast<double>(N - 1);
  if (*low >= std::log(1.5)) {
    g.kind = Growth::Kind::exponential;
    g.entropy = mean;
    g.entropy_error = std::max((*high - *low) / 2, logs.size() < 2 ? mean / 2 : 0.0);
    g.lambda = std::exp(mean);
    g.reason = "no generating function fits; the last " + std::to_string(logs.size()) +
               " ratios d_{n+1}/d_n are all at least 1.5";
  } else if (*high <= std::log1p(4 / n)) {
    g.kind = Growth::Kind::polynomial;
    double sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0;  // slope of log d against log n, last half
    for (std::size_t k = std::max<std::size_t>(N / 2, 1); k < N; ++k) {
      if (d[k] <= 0) continue;
      const double x = std::log(static_cast<double>(k)), y = std::log(d[k]);
      sx += x, sy += y, sxx += x * x, sxy += x * y, m += 1;
    }
    g.degree = m >= 2 ? (m * sxy - sx * sy) / (m * sxx - sx * sx) : 0;
    g.reason = "no generating function fits; the last ratios d_{n+1}/d_n are at most 1 + 4/n "
               "(growth no faster than n^4); the degree is the slope of log d against log n";
  } else {
    g.reason = "no generating function fits, and the last ratios d_{n+1}/d_n (from " +
               std::to_string(std::exp(*low)) + " to " + std::to_string(std::exp(*high)) +
               ") are neither clearly exponential nor polynomial";
  }
  return g;
}

}  // namespace

std::string to_string(Growth::Kind kind) {
  switch (kind) {
    case Growth::Kind::polynomial: return "polynomial";
    case Growth::Kind::exponential: return "exponential";
    default: return "undecided";
  }
}

Growth fit_growth(const std::vector<double>& d, bool integers) {
  if (integers && !d.empty()) {
    std::vector<mpq_class> s;
    for (const double v : d) s.emplace_back(mpz_class(static_cast<long>(v)));
    std::size_t L = 0;
    const Poly C = berlekamp_massey(s, L);
    if (L >= 1 && 2 * L + 4 <= s.size()) return from_recurrence(s, C, L);
  }
  return from_tail(d);
}

}  // namespace qmaps::exact
