/// \file
/// \brief Temperature-aware dN: a polynomial dN(T) fitted to calibrations at several
/// temperatures, with the covariance of its coefficients (METHOD-NOTES.md).
#pragma once

#include <cstddef>
#include <limits>
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
  /// How the runs were pooled: true for fit_delta_n_random_effects (between-run variance
  /// estimated, Knapp-Hartung covariance), false for the within-error weighted fit (files
  /// before schema 3, a `--delta-n`).
  bool random_effects = false;
  /// The between-run variance tau^2 of dN about the model ((deg/s)^2; DerSimonian-Laird), NaN
  /// when not estimated.
  double between_run_var_dps2 = std::numeric_limits<double>::quiet_NaN();
  std::size_t dof = 0;  ///< runs less coefficients (0: the model passes through its runs)
  /// The variance of a new run's dN about the true dN(T) ((deg/s)^2): a new power-up's
  /// between-run change and that run's within-run error (the runs' mean), on Knapp-Hartung's
  /// scale: q (tau^2 + mean v_i) (fit_delta_n_random_effects). NaN when not estimated (no degrees
  /// of freedom, a weighted fit, a model read from a file).
  double new_run_var_dps2 = std::numeric_limits<double>::quiet_NaN();
  /// A between-run variance that changes with temperature (review of issue 31, H3: a
  /// per-power-up change of the g-term's temperature coefficient makes runs scatter more away
  /// from the middle): tau^2(T) = tau2_centre_dps2 + tau2_curvature_dps2_per_c2 (T - t_ref_c)^2,
  /// estimated by moments from the runs' squared residuals under tau0^2, tau1^2 >= 0
  /// (non-negative least squares; fit_delta_n_random_effects), NaN when the runs cannot
  /// estimate it (degree 0, fewer than 3 degrees of freedom, fewer than two distinct
  /// |T - t_ref_c|, a between-run variance below 5 times the runs' mean own, or a curvature
  /// whose moment estimate is below 0.85 of its own standard error: not resolved). Never
  /// negative.
  double tau2_centre_dps2 = std::numeric_limits<double>::quiet_NaN();
  double tau2_curvature_dps2_per_c2 = std::numeric_limits<double>::quiet_NaN();
  /// The fitted runs and their weights 1/(v_i + tau^2), kept for new_run_interval_at's
  /// temperature-dependent band (empty when tau2_centre_dps2 is NaN, and in a model read from a
  /// file).
  std::vector<delta_n_point> fitted_runs;
  std::vector<double> fitted_weights;

  [[nodiscard]] std::size_t degree() const noexcept { return coeffs_dps.size() - 1; }
  /// dN at `temp_c` (deg/s). For degree 0 the temperature is not used (may be NaN).
  [[nodiscard]] double eval(double temp_c) const noexcept;
  /// Standard error of dN(temp_c) from the coefficient covariance (deg/s).
  [[nodiscard]] double stderr_at(double temp_c) const noexcept;
  /// Half-width of the 68.3 % interval of dN(temp_c) (deg/s): stderr_at x Student's t for `dof`
  /// (analysis::t_one_sigma) for a random-effects fit, stderr_at otherwise (older fits have
  /// no dof).
  [[nodiscard]] double interval_at(double temp_c) const;
  /// Half-width of the 68.3 % prediction interval of the dN that a new run (a new power-up,
  /// measured like the fitted runs) gives at `temp_c`, about eval(temp_c) (deg/s): Student's t
  /// for `dof` (analysis::t_one_sigma) x sqrt(stderr_at^2 + new_run_var_dps2), the prediction
  /// interval of a weighted regression whose weights 1/(v_i + tau^2) are known up to
  /// Knapp-Hartung's scale q (Higgins, Thompson & Spiegelhalter 2009, J. R. Stat. Soc. A 172,
  /// 137-159, sec. 5, for a new study's tau^2 + se^2). Where interval_at holds the true line,
  /// this holds a new run: the runs the model was fitted to lie inside it more often (their own
  /// residuals are smaller than a new run's by their leverage). NaN without new_run_var_dps2.
  /// Where tau^2(T) is estimated (tau2_centre_dps2 finite) the interval is instead that of a
  /// between-run variance that depends on T: the variance of a new run about eval(T),
  /// tau^2(T) + mean v_i + the fitted line's variance sum_j g_j(T)^2 (v_j + tau^2(T_j)), is a
  /// linear combination of the squared residuals, and Student's t takes Satterthwaite's (1946,
  /// Biometrics Bull. 2, 110-114) degrees of freedom 2 V^2 / var(V), at least 1; never below
  /// interval_at (docs/METHOD-NOTES.md, "A run-to-run spread that depends on temperature").
  [[nodiscard]] double new_run_interval_at(double temp_c) const;
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

/// The random-effects fit of dN(T) to several runs (issue 31): each run's dN scatters about the
/// model by its within-run error v_i = stderr_i^2 and by a between-run variance tau^2 (a
/// per-power-up change, paper Tab. 3/4: runs scatter 14-30 times their own errors).
/// tau^2 by the method of moments of DerSimonian & Laird (1986, Controlled Clinical Trials 7,
/// 177-188), in its meta-regression form (the method-of-moments estimator of metafor's
/// rma(method = "DL"), Viechtbauer 2010, J. Stat. Softw. 36(3)): tau^2 = max(0, (Q - (k - p)) /
/// (sum w - tr((X'WX)^-1 X'W^2X))), Q the weighted residual sum of squares with w = 1/v. The
/// coefficients are weighted by 1/(v_i + tau^2), and their covariance is Knapp & Hartung's
/// (2003, Statistics in Medicine 22, 2693-2710): (X'W*X)^-1 times q = sum w*_i r_i^2 / (k - p),
/// in its modified form q* = max(1, q) (Roever, Knapp & Friede 2015, BMC Med. Res. Methodol.
/// 15:99; Jackson et al. 2017, Stat. Med. 36, 3923-3934), so that the error is never below the
/// fixed-effect error sqrt(1 / sum 1/(v_i + tau^2)) when a few runs happen to agree (fourth review
/// of issue 31, F1; equal weights of 1, for runs without within-run errors: q itself), whose 68.3 %
/// interval takes Student's t with k - p degrees of freedom (interval_at); a new run's variance
/// about the line is q (tau^2 + the runs' mean v_i) (new_run_interval_at). Measured coverage of
/// that interval: 0.67-0.69 for 2-13 runs with tau from 0 to 10 within-run errors
/// (docs/METHOD-NOTES.md, "Pooling runs"), where the weighted fit's Birge-scaled error covers
/// 0.44-0.73. When tau^2 dwarfs the within-run errors the mean is the runs' plain mean and the
/// slope the ordinary least-squares slope. Without degrees of freedom (k = p) there is no tau^2
/// and no error: the covariance is 0 and dof 0. For degree >= 1 with 3 or more degrees of
/// freedom, two or more distinct |T - T_ref| and tau^2 at least 5 times the runs' mean v_i
/// (runs scattering 2.2 times their own errors or more) it also estimates tau^2(T)
/// (tau2_centre_dps2, tau2_curvature_dps2_per_c2; moments of the squared residuals, Rao 1970,
/// solved under tau0^2, tau1^2 >= 0 by non-negative least squares, Lawson & Hanson 1974), where
/// the curvature's moment estimate is at least 0.85 of its standard error (a preliminary test,
/// Bancroft 1944), which new_run_interval_at then uses. Errors: those of fit_delta_n_model.
[[nodiscard]] result<delta_n_model> fit_delta_n_random_effects(
    std::span<const delta_n_point> points, std::size_t degree);

}  // namespace gyroflip::method
