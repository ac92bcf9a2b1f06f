#pragma once
// How a sequence grows: the degrees of a map's iterates, or the logarithms of their heights.
//
// fit_recurrence: the shortest linear recurrence d_n = c_1 d_{n−1} + … + c_L d_{n−L} with rational
// c_i that the whole sequence satisfies (Berlekamp–Massey over Q, GMP's rationals), taken as found
// only where the sequence has at least 2L + 4 terms: 2L determine it, the rest are predictions it
// got right. Its generating function is Σ d_n z^n = P(z)/Q(z), Q(z) = 1 − c_1 z − … − c_L z^L.
// The growth comes from the characteristic polynomial χ(x) = x^L − c_1 x^{L−1} − … − c_L, factored
// over Z (FLINT): a root of modulus λ > 1 (the largest, from Eigen's eigenvalues of the companion
// matrix) is exponential growth, entropy log λ; else the roots on the unit circle are roots of unity
// (cyclotomic factors, FLINT), and the largest multiplicity m among them gives growth like n^(m−1).
//
// Without a recurrence, the tail: λ from the last ratios d_{n+1}/d_n (their geometric mean, the
// uncertainty half their range), the polynomial degree from the slope of log d against log n.
#include <cstddef>
#include <string>
#include <vector>

namespace qmaps::exact {

struct Growth {
  enum class Kind { polynomial, exponential, undecided } kind = Kind::undecided;
  bool recurrence = false;                // a generating function was found
  std::vector<std::string> coefficients;  // c_1 … c_L as rationals ("3", "-1/2")
  std::string generating_function;        // "P(z)/Q(z)" with the polynomials written out
  std::string characteristic;             // χ factored over Z, "(x - 1)^3*(x + 1)"
  double lambda = 1;                      // the growth rate (exponential)
  double entropy = 0, entropy_error = 0;  // log λ and its uncertainty
  double degree = 0;                      // the polynomial degree (growth like n^degree)
  std::string reason;                     // one line: why this kind
};

std::string to_string(Growth::Kind kind);

// The growth of d_0, d_1, … (degrees: integers; for `integers` false, any positive values, fitted
// by the tail alone).
Growth fit_growth(const std::vector<double>& d, bool integers = true);

}  // namespace qmaps::exact
