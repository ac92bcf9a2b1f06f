#include "core/invariant_discovery.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <Eigen/Dense>
#include <Eigen/SVD>

namespace qmaps {
namespace {

// New rows gathered before they are folded into R: the cost of a fold, (N + chunk)·N² flops,
// spread over `chunk` rows, is then at most 1.5 N² per row, as for the QR of all rows at once.
std::size_t chunk_of(std::size_t columns) { return std::max<std::size_t>(2 * columns, 256); }

using Strided = Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;

}  // namespace

DifferenceRows::DifferenceRows(Monomials monomials)
    : monomials_(std::move(monomials)),
      columns_(monomials_.size()),
      capacity_(columns_ + chunk_of(columns_)),
      block_(capacity_ * columns_),
      mx_(columns_),
      my_(columns_) {}

double DifferenceRows::bytes(double n) {
  // The block (N + chunk) × N, then in discover() R̃, V, the SVD's working copy and U's share.
  const double chunk = std::max(2 * n, 256.0);
  return 8 * (n * (n + chunk) + 4 * n * n);
}

bool DifferenceRows::add(std::span<const double> x, std::span<const double> y) {
  monomials_.evaluate(x, mx_);
  monomials_.evaluate(y, my_);
  for (std::size_t j = 0; j < columns_; ++j) {
    my_[j] -= mx_[j];
    if (!std::isfinite(my_[j])) return false;
  }
  if (filled_ == capacity_) fold();
  for (std::size_t j = 0; j < columns_; ++j) block_[j * capacity_ + filled_] = my_[j];
  ++filled_;
  ++rows_;
  return true;
}

void DifferenceRows::fold() {
  // [R; new rows] = Q' R': R' replaces them (Householder QR in place; its vectors, stored below
  // the diagonal, are cleared).
  Strided a(block_.data(), static_cast<Eigen::Index>(filled_),
            static_cast<Eigen::Index>(columns_), Eigen::OuterStride<>(static_cast<Eigen::Index>(capacity_)));
  Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>> ref(a);
  Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>>> qr(ref);
  const std::size_t kept = std::min(filled_, columns_);
  for (std::size_t j = 0; j < columns_; ++j)
    for (std::size_t i = j + 1; i < filled_; ++i) block_[j * capacity_ + i] = 0;
  filled_ = kept;
}

std::vector<double> DifferenceRows::triangular() {
  fold();
  std::vector<double> r(filled_ * columns_);
  for (std::size_t j = 0; j < columns_; ++j)
    for (std::size_t i = 0; i < filled_; ++i) r[j * filled_ + i] = block_[j * capacity_ + i];
  return r;
}

Discovery discover(DifferenceRows& rows, const DiscoveryOptions& options) {
  const std::size_t n = rows.monomials().size();
  if (rows.rows() < n)
    throw std::invalid_argument("discover: " + std::to_string(rows.rows()) + " rows for " +
                                std::to_string(n) + " monomials");
  Discovery d;
  d.rows = rows.rows();
  d.monomials = n;
  const std::vector<double> r_data = rows.triangular();
  const auto N = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd r = Eigen::Map<const Eigen::MatrixXd>(r_data.data(), N, N);

  // Unit columns: R̃ = R S⁻¹ (a column that is 0 on all data stays 0: its monomial is invariant).
  d.scales.resize(n);
  for (Eigen::Index j = 0; j < N; ++j) {
    const double s = r.col(j).norm();
    d.scales[static_cast<std::size_t>(j)] = s > 0 ? s : 1;
    r.col(j) /= d.scales[static_cast<std::size_t>(j)];
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(r, Eigen::ComputeFullV);
  const Eigen::VectorXd sigma = svd.singularValues();
  d.largest = sigma(0);
  d.relative.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    d.relative[i] = d.largest > 0 ? sigma(static_cast<Eigen::Index>(i)) / d.largest : 0;
  // σ_i/σ_{i+1} (i 1-based), both taken as at least 2⁻⁵⁶ σ_1: below round-off every singular value
  // is zero alike (exact zeros come from a monomial constant on all the data), and no gap opens
  // between them.
  const auto ratio = [&](std::size_t i) {
    constexpr double floor = 0x1p-56;
    return std::max(d.relative[i - 1], floor) / std::max(d.relative[i], floor);
  };
  for (std::size_t i = 1; i < n; ++i)
    if (ratio(i) > d.largest_gap) {
      d.largest_gap = ratio(i);
      d.largest_gap_at = i;
    }
  if (options.threshold > 0) {
    while (d.dimension < n && d.relative[n - 1 - d.dimension] <= options.threshold) ++d.dimension;
  } else {  // at the largest gap among the small singular values
    double best = 0;
    for (std::size_t i = 1; i < n; ++i)
      if (d.relative[i] <= options.ceiling && ratio(i) > best) {
        best = ratio(i);
        if (best >= options.minimum_gap) d.dimension = n - i;
      }
  }
  if (d.dimension > 0 && d.dimension < n) d.gap = ratio(n - d.dimension);

  const std::size_t k = d.dimension;
  if (k == 0) return d;
  Eigen::MatrixXd basis(static_cast<Eigen::Index>(k), N);  // rows: ṽ_i
  for (std::size_t i = 0; i < k; ++i) {
    const Eigen::VectorXd v = svd.matrixV().col(N - 1 - static_cast<Eigen::Index>(i));
    basis.row(static_cast<Eigen::Index>(i)) = v.transpose();
    d.null_space.emplace_back(v.data(), v.data() + n);
  }

  // Reduced row echelon form, pivots in monomial order, chosen by size (partial pivoting).
  const double tolerance = options.pivot * basis.cwiseAbs().maxCoeff();
  Eigen::Index pivot_row = 0;
  for (Eigen::Index j = 0; j < N && pivot_row < basis.rows(); ++j) {
    Eigen::Index best = 0;
    const double size = basis.col(j).tail(basis.rows() - pivot_row).cwiseAbs().maxCoeff(&best);
    if (!(size > tolerance)) continue;
    if (best != 0) basis.row(pivot_row).swap(basis.row(pivot_row + best));
    basis.row(pivot_row) /= basis(pivot_row, j);
    for (Eigen::Index i = 0; i < basis.rows(); ++i)
      if (i != pivot_row) basis.row(i) -= basis(i, j) * basis.row(pivot_row);
    ++pivot_row;
  }
  for (Eigen::Index i = 0; i < pivot_row; ++i) {
    std::vector<double> c(n);
    double largest = 0;
    for (std::size_t j = 0; j < n; ++j) {
      c[j] = basis(i, static_cast<Eigen::Index>(j)) / d.scales[j];
      if (std::fabs(c[j]) > std::fabs(largest)) largest = c[j];
    }
    for (double& x : c) x /= largest;
    d.invariants.push_back(std::move(c));
  }
  return d;
}

double outside_null_space(const Discovery& d, std::span<const double> coefficients) {
  const std::size_t n = d.monomials;
  Eigen::VectorXd c(static_cast<Eigen::Index>(n));
  for (std::size_t j = 0; j < n; ++j) c(static_cast<Eigen::Index>(j)) = coefficients[j] * d.scales[j];
  const double whole = c.norm();
  for (const auto& v : d.null_space) {
    const Eigen::Map<const Eigen::VectorXd> u(v.data(), static_cast<Eigen::Index>(n));
    c -= u.dot(c) * u;
  }
  return whole > 0 ? c.norm() / whole : 0;
}

PolynomialFit fit_polynomial(const Monomials& monomials,
                             std::span<const std::vector<double>> samples,
                             std::span<const double> values) {
  const auto rows = static_cast<Eigen::Index>(samples.size());
  const auto n = static_cast<Eigen::Index>(monomials.size());
  Eigen::MatrixXd a(rows, n + 1);
  Eigen::VectorXd f(rows);
  std::vector<double> m(monomials.size());
  for (Eigen::Index i = 0; i < rows; ++i) {
    monomials.evaluate(samples[static_cast<std::size_t>(i)], m);
    a(i, 0) = 1;
    for (Eigen::Index j = 0; j < n; ++j) a(i, j + 1) = m[static_cast<std::size_t>(j)];
    f(i) = values[static_cast<std::size_t>(i)];
  }
  Eigen::VectorXd scale = a.colwise().norm().transpose();
  for (Eigen::Index j = 0; j <= n; ++j) {
    if (scale(j) == 0) scale(j) = 1;
    a.col(j) /= scale(j);
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(f);
  PolynomialFit fit;
  fit.residual = f.norm() > 0 ? (a * x - f).norm() / f.norm() : 0;
  fit.constant = x(0) / scale(0);
  for (Eigen::Index j = 0; j < n; ++j) fit.coefficients.push_back(x(j + 1) / scale(j + 1));
  return fit;
}

}  // namespace qmaps
