#include "core/monomials.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace qmaps {

double Monomials::count(std::size_t variables, long long degree) {
  const double n = static_cast<double>(variables);
  if (degree > 1000) {  // C(n + d, n) = Π_{k=1…n} (d + k)/k: n factors, for any d (no lgamma
                        // difference, which cancels to 0 for d near 2^63)
    const double d = static_cast<double>(degree);
    double c = 1;
    for (std::size_t k = 1; k <= variables; ++k)
      c = c * (d + static_cast<double>(k)) / static_cast<double>(k);
    return c - 1;
  }
  // C(n + d, d) = Π_{k=1…d} (n + k)/k, exact in doubles while it stays below 2^53.
  double c = 1;
  for (long long k = 1; k <= degree; ++k) c = c * (n + static_cast<double>(k)) / static_cast<double>(k);
  return std::round(c) - 1;
}

Monomials::Monomials(std::size_t variables, int degree) : variables_(variables), degree_(degree) {
  if (variables == 0 || degree < 1) throw std::invalid_argument("Monomials: n >= 1 and d >= 1");
  // Degree by degree, the exponent vectors of that degree in decreasing lexicographic order: the
  // first variable takes as much as it can, then the rest share what is left, recursively.
  std::vector<int> e(variables);
  const auto fill = [&](auto&& self, std::size_t i, int left) -> void {
    if (i + 1 == variables) {
      e[i] = left;
      exponents_.insert(exponents_.end(), e.begin(), e.end());
      return;
    }
    for (int k = left; k >= 0; --k) {
      e[i] = k;
      self(self, i + 1, left - k);
    }
  };
  for (int d = 1; d <= degree; ++d) fill(fill, 0, d);
  size_ = exponents_.size() / variables;
}

void Monomials::evaluate(std::span<const double> x, std::span<double> out) const {
  // Powers x_i^k for k = 0 … d, then one product per monomial.
  std::vector<double> powers(variables_ * static_cast<std::size_t>(degree_ + 1));
  for (std::size_t i = 0; i < variables_; ++i) {
    double* p = &powers[i * static_cast<std::size_t>(degree_ + 1)];
    p[0] = 1;
    for (int k = 1; k <= degree_; ++k) p[k] = p[k - 1] * x[i];
  }
  for (std::size_t j = 0; j < size_; ++j) {
    double v = 1;
    for (std::size_t i = 0; i < variables_; ++i)
      if (const int k = exponent(j, i)) v *= powers[i * static_cast<std::size_t>(degree_ + 1) + static_cast<std::size_t>(k)];
    out[j] = v;
  }
}

std::string Monomials::text(std::size_t j, std::span<const std::string> names) const {
  std::string out;
  for (std::size_t i = 0; i < variables_; ++i) {
    const int k = exponent(j, i);
    if (k == 0) continue;
    if (!out.empty()) out += ' ';
    out += names[i];
    if (k > 1) out += '^' + std::to_string(k);
  }
  return out;
}

std::string Monomials::polynomial(std::span<const double> c, std::span<const std::string> names,
                                  double drop, int digits) const {
  double largest = 0;
  for (double v : c) largest = std::fmax(largest, std::fabs(v));
  std::string out;
  for (std::size_t j = 0; j < size_; ++j) {
    if (!(std::fabs(c[j]) >= drop * largest) || c[j] == 0) continue;
    char number[40];
    std::snprintf(number, sizeof number, "%.*g", digits, std::fabs(c[j]));
    if (out.empty())
      out += c[j] < 0 ? "-" : "";
    else
      out += c[j] < 0 ? " - " : " + ";
    out += number;
    out += ' ' + text(j, names);
  }
  return out.empty() ? "0" : out;
}

}  // namespace qmaps
