/// \file
/// \brief The whole noise analysis of one series, as `gyroflip noise` and `gyroflip.noise()` run
/// it: OADEV at octave taus with confidence bounds, the IEEE 952 terms fitted over a range of
/// taus (noise_fit.hpp), and the terms read off the curve's slopes (readoffs.hpp).
#pragma once

#include <limits>
#include <span>
#include <vector>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/noise_fit.hpp"
#include "gyroflip/analysis/readoffs.hpp"

namespace gyroflip::analysis {

struct noise_analysis {
  std::vector<deviation_point> oadev;  ///< every octave point, with bounds at the fit's level
  noise_terms terms;                   ///< fitted to the points with tau in the fit range
  slope_readoffs readoffs;             ///< over every point, not only the fitted range
  /// The short taus left out of the default fit as shaped by a filter or a line (none when the
  /// range was given: tau_range::detect_shaping false).
  short_tau_shaping shaping;
  /// OADEV at the factor m = round(1 s / tau0) (tau = m tau0 = 1 s for whole sample rates), and
  /// that tau: the datasheet's "ARW = ADEV(1 s)" (ADEV(tau) sqrt(tau) in deg/s/sqrt(Hz)). NaN
  /// when the record is too short or tau0 > 1 s.
  double adev_1s = std::numeric_limits<double>::quiet_NaN();
  double adev_1s_tau_s = std::numeric_limits<double>::quiet_NaN();
  /// N as ADEV(1 s) gives it once the other fitted terms' AVAR at that tau is taken out:
  /// sqrt((ADEV^2 - 3Q^2/tau^2 - (2 ln2/pi) B^2 - K^2 tau/3 - R^2 tau^2/2) tau) (resolved terms);
  /// what the fitted N is compared with. NaN with adev_1s.
  double adev_1s_arw = std::numeric_limits<double>::quiet_NaN();
  /// With long_taus: the octave points beyond Stable32's m <= (N-1)/4, up to m <= (N-1)/2 (as
  /// MATLAB's allanvar and allantools), with bounds; shown, never fitted.
  std::vector<deviation_point> long_oadev;
};

/// Taus (s) the model is fitted to, both ends included.
struct tau_range {
  double lo_s = 0.0;
  double hi_s = std::numeric_limits<double>::infinity();
  /// Leave the short taus shaped by the sensor's filter or a spectral line out of the fit
  /// (detect_short_tau_shaping). True for the default range; a range the user gives is fitted
  /// as given.
  bool detect_shaping = true;
};

/// The rule for a fit range (`--fit-taus LO:HI`, Python's `fit_taus`): 0 <= LO < HI, LO finite,
/// HI finite or +inf (no upper limit, the default). Error (parameter `fit_taus`) otherwise.
[[nodiscard]] status check_fit_range(const tau_range& range);

/// OADEV of `x` (octave taus), its bounds at `level` (add_confidence), the fit of the points in
/// `range` (less the short taus a filter or line shaped, when range.detect_shaping) and the
/// read-offs. Each term's interval includes the fit-range systematic: the fit is repeated with
/// the one and two shortest fitted taus left out and with the longest left out (each keeping at
/// least 4 points); half the spread of the squared coefficient over these readings is added in
/// quadrature to its standard error, and the interval is widened to hold every reading
/// (noise_term::range_lo/hi). `long_taus`: also the points up to m <= (N-1)/2 (long_oadev). Errors:
/// a level or range the checks above refuse, those of `deviation` and `fit_noise_terms` (too few
/// points in the range).
[[nodiscard]] result<noise_analysis> analyse_noise(const phase_source& x, double level,
                                                   const tau_range& range = {},
                                                   const noise_series& series = {},
                                                   const progress_fn& on_progress = {},
                                                   bool long_taus = false);

/// analyse_noise over a series with gaps, given as its gap-free parts (phase sources of one
/// tau0): at each octave factor m of the longest part (m <= (N-1)/4) the OADEV of every term of
/// every part that holds one, pooled (sqrt(sum_k n_k OADEV_k^2 / sum_k n_k): GRADEV's sum over
/// the terms whose points all exist, Sesia, Tavella et al., Metrologia 2008; the same values as
/// `gradev` of the parts on one grid with NaN between them), its EDF the sum of the parts' (each
/// part's own, guarded rule; the parts taken as independent), its bounds at `level` from that
/// EDF (chi-square), then the same fit as above. No long taus; ADEV(1 s) only when 1 s is one of
/// the factors. A single part gives analyse_noise's curve, bounds and terms. Errors: as
/// analyse_noise, and no part long enough for a factor.
[[nodiscard]] result<noise_analysis> analyse_noise(std::span<const phase_source* const> parts,
                                                   double level, const tau_range& range = {},
                                                   const noise_series& series = {});

}  // namespace gyroflip::analysis
