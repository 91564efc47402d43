/// \file
/// \brief The one weighted linear least-squares solver of gyroflip (Eigen inside; no Eigen in this
/// header): minimise chi^2 = sum_i w_i (y_i - sum_k A_ik c_k)^2, with the covariance of c.
/// Used by the IEEE 952 noise fit (noise_fit.hpp) and the dN(T) model (method/delta_n_model.hpp).
///
/// Method: the columns of sqrt(W) A are scaled to unit norm (the noise-fit basis spans ten
/// decades), then column-pivoting Householder QR (Golub & Van Loan, "Matrix Computations", 4th
/// ed., section 5.4.2): c = R^-1 Q^T sqrt(W) y and cov(c) = (A^T W A)^-1 = R^-1 R^-T, unscaled.
/// QR on sqrt(W) A, not the normal equations, keeps the condition number unsquared.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::analysis {

struct wls_fit {
  std::vector<double> coeffs;  ///< c, one per column
  std::vector<double> cov;     ///< (A^T W A)^-1, row-major cols x cols
  double chi2 = 0.0;           ///< sum_i w_i r_i^2 at the solution
};

/// Solves for `cols` coefficients; `design` is A row-major (y.size() rows), `weights` w_i >= 0.
/// Errors (runtime): fewer rows than columns, a rank-deficient weighted design (relative
/// tolerance 1e-12), or non-finite input.
[[nodiscard]] result<wls_fit> weighted_least_squares(std::span<const double> design,
                                                     std::size_t cols, std::span<const double> y,
                                                     std::span<const double> weights);

}  // namespace gyroflip::analysis
