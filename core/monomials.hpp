#pragma once
// The monomials of n variables of degree 1 … d, the columns of invariant discovery
// (core/invariant_discovery.hpp): m(x) = (x^e)_e with x^e = x_1^{e_1} ⋯ x_n^{e_n} and
// 1 ≤ |e| = e_1 + … + e_n ≤ d. There are C(n + d, d) − 1 of them (the constant left out). They are
// ordered by degree, and within a degree by exponents in decreasing lexicographic order
// (x1², x1x2, x1x3, …, x2², …), so that a reduced form over them reads lowest degrees first.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace qmaps {

class Monomials {
 public:
  Monomials(std::size_t variables, int degree);

  // C(n + d, d) − 1, as a double (exact below 2^53, for large d from lgamma): it says how big a
  // degree would be before anything is allocated.
  static double count(std::size_t variables, long long degree);

  std::size_t size() const { return size_; }
  std::size_t variables() const { return variables_; }
  int degree() const { return degree_; }
  // The exponent of variable i in monomial j.
  int exponent(std::size_t j, std::size_t i) const { return exponents_[j * variables_ + i]; }

  // out[j] = monomial j at x (x.size() = variables(), out.size() = size()).
  void evaluate(std::span<const double> x, std::span<double> out) const;

  // Monomial j written with these variable names: "q1^2 p2", "q1[n] q2[n+1]^3".
  std::string text(std::size_t j, std::span<const std::string> names) const;
  // Σ_j c_j m_j, e.g. "1 q1^2 + 0.5 p1^2 - 0.25 q1^2 q2^2": terms in monomial order, each
  // coefficient with `digits` significant digits; terms with |c_j| < drop · max|c| are left out.
  std::string polynomial(std::span<const double> coefficients,
                         std::span<const std::string> names, double drop,
                         int digits = 8) const;

 private:
  std::size_t variables_;
  int degree_;
  std::size_t size_ = 0;
  std::vector<int> exponents_;  // [monomial][variable]
};

}  // namespace qmaps
