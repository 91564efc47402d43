/// \file
/// \brief IEEE Std 952-1997 Annex C noise terms of a gyro from its Allan variance: quantisation
/// Q, angle random walk N, bias instability B, rate random walk K, rate ramp R.
///
/// Model (FACTS §7): AVAR(tau) = 3Q^2/tau^2 + N^2/tau + (2 ln2/pi) B^2 + K^2 tau/3 +
/// R^2 tau^2/2, linear in the squared coefficients. Fitted to OADEV points by weighted least
/// squares with weights edf/(2 AVAR_model^2) (the chi-squared variance of each AVAR estimate),
/// iterated three times; every subset of the five terms is solved and the best non-negative
/// one kept, so a term the data cannot support is dropped rather than made negative.
/// Intervals come from the sandwich covariance of the squared coefficients, with the AVAR
/// estimates correlated between taus as overlapping estimates of one series are (noise-type
/// dependent; docs/ANALYSIS.md), so that they cover the truth at about their nominal level.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/analysis/allan.hpp"

namespace gyroflip::analysis {

/// One fitted term: its coefficient and interval (squared coefficient +- z standard errors,
/// z for the fit's two-sided level), or unresolved with an upper limit.
struct noise_term {
  bool resolved = false;  ///< the squared coefficient exceeds twice its standard error
  double value = 0.0;     ///< coefficient in the term's base unit (see noise_terms)
  double lo = 0.0;        ///< lower end of the interval (resolved terms)
  double hi = 0.0;        ///< upper end; for unresolved terms the upper limit
  /// The lowest and highest value the term takes over the alternative fit ranges (the default
  /// range with one or two more short taus left out, and with the longest tau left out;
  /// analyse_noise): the fit-range systematic, which [lo, hi] includes. Equal to `value` when
  /// only one range was fitted or no alternative resolved the term.
  double range_lo = 0.0, range_hi = 0.0;
};

/// Where the shortest taus of an Allan curve are shaped by something that is not one of the five
/// IEEE 952 terms (detect_short_tau_shaping).
struct short_tau_shaping {
  std::size_t points = 0;  ///< leading points left out of the fit (0: none)
  /// "filter": the sensor's low-pass (anti-alias) roll-off, the curve below the N/sqrt(tau) line
  /// and bending down to it; "line": a spectral line (a sinusoid's bumps, alternating kinks).
  std::string cause;
  double kink_tau_s = 0.0;  ///< tau of the last significant concave kink (the last point left out)
  double kink_z = 0.0;      ///< its significance (kink / standard error)
};

/// A point where the fitted model leaves the measured point's interval.
struct misfit_point {
  double tau_s = 0.0;
  double dev = 0.0;        ///< measured OADEV
  double model_dev = 0.0;  ///< the fitted model's ADEV there
  double ci_lo = 0.0;
  double ci_hi = 0.0;
};

/// Coefficients in base units: Q deg, N deg/s/sqrt(Hz) (= deg/sqrt(s)), B deg/s,
/// K deg/s/sqrt(s), R deg/s^2.
struct noise_terms {
  noise_term quantization, arw, bias_instability, rrw, rate_ramp;
  double bias_floor_tau_s = 0.0;  ///< tau of the first local minimum of OADEV (or the last point)
  double bias_floor_dev = 0.0;    ///< OADEV there (deg/s)
  bool bias_floor_reached =
      false;  ///< false: OADEV still falls at the longest tau (B bounded only)
  /// tau (s) within the data's taus where the fitted model is lowest: where a plot marks the
  /// fitted flicker floor 0.664 B (a model's minimum, not a measured point's)
  double fit_min_tau_s = 0.0;
  std::vector<misfit_point> misfit;  ///< points whose interval the fitted model misses
  double chi2_per_dof = 0.0;         ///< weighted fit quality
  double level = 0.683;              ///< two-sided confidence level of the intervals
  std::vector<std::string> notes;    ///< terms not resolved, and why
  double fit_tau_lo_s = 0.0;         ///< the shortest tau fitted
  double fit_tau_hi_s = 0.0;         ///< the longest tau fitted
  std::size_t fit_ranges = 1;        ///< ranges fitted for the fit-range systematic (1: none)
};

/// What the analysed series is, where that changes the model.
struct noise_series {
  /// > 0: the series is a demodulator's estimates (method/demodulator.hpp) spaced this far apart
  /// (s).
  double cycle_s = 0.0;
  /// The demodulator's white-noise Allan shape: white dwell noise gives its estimate series AVAR
  /// N^2 (1/tau - kappa T/tau^2) (method::noise_transfer::white_avar_deficit; abba 9/16:
  /// neighbouring estimates share dwells, docs/ANALYSIS.md), which the ARW term then uses;
  /// without it the 44 % deficit at tau = T reads as a bias-instability floor. 0: uncorrelated.
  double white_avar_deficit = 0.0;
  /// What the fit's notes say of the shape (the demodulator's words, method::noise_series_of).
  std::string note;
  /// Whether the white term has the demodulator's shape (a known short-tau shape).
  [[nodiscard]] bool shaped() const noexcept { return cycle_s > 0.0 && white_avar_deficit > 0.0; }
};

/// The leading points of `pts` (OADEV at octave taus with EDF and alpha, increasing tau) that the
/// five-term model cannot describe. Every term's tau*AVAR is a power of tau with a non-negative
/// coefficient, so the model's log-log curve is convex: the slope of its ADEV never decreases
/// with tau. A decreasing slope (a concave kink at point j: slope(j-1, j) - slope(j, j+1) > 0)
/// is shaped by something else: a low-pass filter (the curve rises from below to the N line,
/// first-octave slope -0.31 instead of -1/2 on the ADIS16405) or a spectral line (bumps that
/// alternate). Kinks are tested against their standard error (Var ln sigma = 1/(2 edf), the
/// octaves correlated as in the fit's sandwich); the points up to the last kink with z >= 3.5
/// whose left segment still falls steeper than -1/4 and that lies before the first local minimum
/// are left out, keeping at least 4 points. docs/ANALYSIS.md, "Short taus shaped by the filter".
[[nodiscard]] short_tau_shaping detect_short_tau_shaping(std::span<const deviation_point> pts);

/// Fits the IEEE 952 terms to OADEV points carrying EDF and alpha (add_confidence), with
/// intervals at two-sided confidence `level` in (0, 1) (0.683 = 1 sigma). Needs >= 3 points.
/// B is reported as resolved only where OADEV has a floor (a local minimum before the last
/// point); points whose interval the fitted model misses are listed in `misfit`.
[[nodiscard]] result<noise_terms> fit_noise_terms(std::span<const deviation_point> pts,
                                                  double level = 0.683,
                                                  const noise_series& series = {});

}  // namespace gyroflip::analysis
