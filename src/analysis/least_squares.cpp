/// \file
/// \brief Weighted least squares by column-pivoting QR (see least_squares.hpp). The only Eigen
/// translation unit of the library (Eigen headers compile slowly: keep them here).
#include "gyroflip/analysis/least_squares.hpp"

#include <cmath>

#include <Eigen/Dense>

#include "gyroflip/core/error.hpp"

namespace gyroflip::analysis {

result<wls_fit> weighted_least_squares(std::span<const double> design, std::size_t cols,
                                       std::span<const double> y, std::span<const double> weights) {
  const std::size_t rows = y.size();
  if (cols == 0 || rows < cols || design.size() != rows * cols || weights.size() != rows)
    return runtime_error("least squares: fewer observations than unknowns");
  const auto r = static_cast<Eigen::Index>(rows);
  const auto c = static_cast<Eigen::Index>(cols);
  Eigen::MatrixXd a(r, c);
  Eigen::VectorXd b(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    const double w = weights[static_cast<std::size_t>(i)];
    if (!(w >= 0.0) || !std::isfinite(w) || !std::isfinite(y[static_cast<std::size_t>(i)]))
      return runtime_error("least squares: non-finite data or weight");
    const double sw = std::sqrt(w);
    b(i) = sw * y[static_cast<std::size_t>(i)];
    for (Eigen::Index k = 0; k < c; ++k) {
      const double v = design[static_cast<std::size_t>(i * c + k)];
      if (!std::isfinite(v)) return runtime_error("least squares: non-finite design");
      a(i, k) = sw * v;
    }
  }
  // Unit-norm columns: the solve and the rank decision do not depend on the units of c_k.
  Eigen::VectorXd scale(c);
  for (Eigen::Index k = 0; k < c; ++k) {
    const double norm = a.col(k).norm();
    if (!(norm > 0.0)) return runtime_error("least squares: a column has no weight");
    scale(k) = 1.0 / norm;
    a.col(k) *= scale(k);
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-12);
  if (qr.rank() < c) return runtime_error("least squares: the design is rank deficient");
  const Eigen::VectorXd cs = qr.solve(b);
  // (A_s^T A_s)^-1 = P R^-1 R^-T P^T for A_s P = Q R.
  const Eigen::MatrixXd rr = qr.matrixR().topLeftCorner(c, c).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd rinv =
      rr.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(c, c));
  const Eigen::MatrixXd p = qr.colsPermutation();
  const Eigen::MatrixXd cov_s = p * (rinv * rinv.transpose()) * p.transpose();
  wls_fit out;
  out.coeffs.resize(cols);
  out.cov.resize(cols * cols);
  for (Eigen::Index k = 0; k < c; ++k) out.coeffs[static_cast<std::size_t>(k)] = cs(k) * scale(k);
  for (Eigen::Index i = 0; i < c; ++i)
    for (Eigen::Index j = 0; j < c; ++j)
      out.cov[static_cast<std::size_t>(i * c + j)] = cov_s(i, j) * scale(i) * scale(j);
  out.chi2 = (a * cs - b).squaredNorm();
  return out;
}

}  // namespace gyroflip::analysis
