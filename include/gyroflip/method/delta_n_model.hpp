/// \file
/// \brief Temperature-aware dN: a polynomial dN(T) fitted to calibrations at several
/// temperatures, with the covariance of its coefficients (METHOD-NOTES.md).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::method {

/// Highest degree of a dN(T) polynomial (the CLI's --degree; calibration files are checked).
inline constexpr std::size_t max_model_degree = 6;

/// One calibration: its mean temperature, dN and the standard error of dN.
struct delta_n_point {
  double temp_c = 0.0;
  double delta_n_dps = 0.0;
  double stderr_dps = 0.0;
};

/// dN(T) = sum_k coeffs_dps[k] (T - t_ref_c)^k. A constant dN is a degree-0 model.
struct delta_n_model {
  std::vector<double> coeffs_dps;  ///< coefficient k in deg/s per degC^k
  double t_ref_c = 0.0;            ///< reference temperature (mean of the fitted points)
  std::vector<double> cov;         ///< (K+1)x(K+1) row-major covariance of the coefficients
  double temp_min_c = 0.0;         ///< temperature range the fit covers
  double temp_max_c = 0.0;
  double chi2_per_dof = 0.0;  ///< fit quality (0 when there are no degrees of freedom)

  [[nodiscard]] std::size_t degree() const noexcept { return coeffs_dps.size() - 1; }
  /// dN at `temp_c` (deg/s). For degree 0 the temperature is not used (may be NaN).
  [[nodiscard]] double eval(double temp_c) const noexcept;
  /// Standard error of dN(temp_c) from the coefficient covariance (deg/s).
  [[nodiscard]] double stderr_at(double temp_c) const noexcept;
};

/// A constant dN with its standard error (from `--delta-n` or a one-file calibration).
[[nodiscard]] delta_n_model constant_model(double delta_n_dps, double stderr_dps = 0.0);

/// Weighted least-squares polynomial fit of dN(T) of degree `degree`, weights 1/stderr^2
/// (all equal if any stderr is zero or at rounding level, below 1e-12 |dN|). The coefficient
/// covariance (X'WX)^-1 is scaled by max(1, chi^2/dof) (Birge ratio), because run-to-run scatter of
/// dN is usually larger than each run's own error (paper Tab. 3). Errors: fewer distinct
/// temperatures than degree + 1, non-finite input, degree > 6.
[[nodiscard]] result<delta_n_model> fit_delta_n_model(std::span<const delta_n_point> points,
                                                      std::size_t degree);

}  // namespace gyroflip::method
