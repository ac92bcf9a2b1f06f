#pragma once
// Polynomial invariants from data. A polynomial I(x) = Σ_j c_j m_j(x) over the monomials m of
// degree 1 … d (core/monomials.hpp; a constant is invariant trivially and is left out) is an
// invariant of a map F when I(F(x)) = I(x). On steps x_k → x_{k+1} of many orbits this is linear
// in c:
//
//     M c = 0,   row k of M:  r_k = m(x_{k+1}) − m(x_k).
//
// With the column norms s_j = ‖M e_j‖ and S = diag(s), M̃ = M S⁻¹ = U Σ Vᵀ (Eigen's JacobiSVD),
// σ_1 ≥ … ≥ σ_N. The numerical null space is spanned by the right singular vectors ṽ_i with
// σ_i/σ_1 ≤ τ (a threshold, or by default the place of the largest gap among the small singular
// values), and each gives the coefficients c = S⁻¹ ṽ_i of an invariant. The gap σ_k/σ_{k+1} at
// k = N − dim says how clearly it is separated from the rest; 1/gap bounds the angle between the
// discovered span and the exact one, and so the coefficients' relative error.
//
// M is never held whole: rows are gathered in blocks and folded into the triangular factor R of
// M = QR (Householder QR of [R; new rows]), which has M's singular values and right singular
// vectors and N² entries however many rows there are. Column norms are R's (‖M e_j‖ = ‖R e_j‖).
//
// The basis is then put in reduced row echelon form over the monomials in their order (pivots
// chosen on the scaled coefficients, the first monomial whose largest entry among the remaining
// rows exceeds a tolerance): a canonical basis of the span, independent of the SVD's rotation.
// Each basis invariant is finally scaled so that its largest coefficient is 1.
#include <cstddef>
#include <span>
#include <vector>

#include "core/monomials.hpp"

namespace qmaps {

// The rows m(x_{k+1}) − m(x_k), folded into R as they come.
class DifferenceRows {
 public:
  explicit DifferenceRows(Monomials monomials);
  // The bytes that DifferenceRows and discover() hold for `monomials` columns: the block [R; new
  // rows] and the SVD's matrices. Check it before constructing one.
  static double bytes(double monomials);

  const Monomials& monomials() const { return monomials_; }
  // Adds the row of the step x → y (each of monomials().variables() values). A row that is not
  // finite (a monomial overflowed) is not added, and false is returned.
  bool add(std::span<const double> x, std::span<const double> y);
  std::size_t rows() const { return rows_; }
  // R (min(rows, N) × N, upper triangular, column-major) of all rows so far.
  std::vector<double> triangular();

 private:
  void fold();
  Monomials monomials_;
  std::size_t columns_, capacity_;
  std::size_t filled_ = 0;  // rows of block_ in use: R's on top, then the rows not yet folded
  std::size_t rows_ = 0;
  std::vector<double> block_;  // capacity_ × columns_, column-major
  std::vector<double> mx_, my_;
};

struct DiscoveryOptions {
  // τ: σ_i/σ_1 ≤ τ is null. 0: at the largest gap σ_k/σ_{k+1} among those with σ_{k+1}/σ_1 ≤
  // `ceiling`, if it is at least `minimum_gap` (else the null space is empty).
  double threshold = 0;
  double ceiling = 1e-6;
  double minimum_gap = 1e3;
  double pivot = 1e-6;  // a reduced-form pivot exceeds this times the largest scaled entry
};

struct Discovery {
  std::size_t rows = 0, monomials = 0;
  double largest = 0;            // σ_1
  std::vector<double> relative;  // σ_i/σ_1, decreasing
  std::size_t dimension = 0;     // of the null space
  // σ_k/σ_{k+1} at k = N − dimension, each at least 2⁻⁵⁶ σ_1 (0 when dimension is 0 or N).
  double gap = 0;
  // The largest ratio σ_i/σ_{i+1} of the spectrum, at i (1-based; 0 when N = 1).
  std::size_t largest_gap_at = 0;
  double largest_gap = 0;
  std::vector<double> scales;                   // s_j (1 where the column is 0)
  std::vector<std::vector<double>> null_space;  // ṽ_i, orthonormal, scaled coordinates
  std::vector<std::vector<double>> invariants;  // the reduced basis: c_j of m_j, max |c_j| = 1
};

// The null space of the rows (they must number at least the monomials; throws otherwise).
Discovery discover(DifferenceRows& rows, const DiscoveryOptions& options = {});

// ‖(1 − P) S c‖/‖S c‖: the part of the invariant with coefficients c (of the monomials) that lies
// outside the discovered null space (P its projector), in the scaled coordinates; 0 when the
// invariant is a combination of the discovered ones.
double outside_null_space(const Discovery& d, std::span<const double> coefficients);

// The least-squares fit f(x) ≈ c_0 + Σ_j c_j m_j(x) of values f at samples x (e.g. a known
// invariant evaluated on states), to compare a formula with the discovered invariants.
struct PolynomialFit {
  double constant = 0;
  std::vector<double> coefficients;  // c_j of m_j
  double residual = 0;               // rms of the fit's error / rms of f
};
PolynomialFit fit_polynomial(const Monomials& monomials,
                             std::span<const std::vector<double>> samples,
                             std::span<const double> values);

}  // namespace qmaps
