/// \file
/// \brief The whole noise analysis of one series, as `gyroflip noise` and `gyroflip.noise()` run
/// it: OADEV at octave taus with confidence bounds, the IEEE 952 terms fitted over a range of
/// taus (noise_fit.hpp), and the terms read off the curve's slopes (readoffs.hpp).
#pragma once

#include <limits>
#include <vector>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/noise_fit.hpp"
#include "gyroflip/analysis/readoffs.hpp"

namespace gyroflip::analysis {

struct noise_analysis {
  std::vector<deviation_point> oadev;  ///< every octave point, with bounds at the fit's level
  noise_terms terms;                   ///< fitted to the points with tau in the fit range
  slope_readoffs readoffs;             ///< over every point, not only the fitted range
};

/// Taus (s) the model is fitted to, both ends included.
struct tau_range {
  double lo_s = 0.0;
  double hi_s = std::numeric_limits<double>::infinity();
};

/// The rule for a fit range (`--fit-taus LO:HI`, Python's `fit_taus`): 0 <= LO < HI, LO finite,
/// HI finite or +inf (no upper limit, the default). Error (parameter `fit_taus`) otherwise.
[[nodiscard]] status check_fit_range(const tau_range& range);

/// OADEV of `x` (octave taus), its bounds at `level` (add_confidence), the fit of the points in
/// `range` and the read-offs. Errors: a level or range the checks above refuse, those of
/// `deviation` and `fit_noise_terms` (too few points in the range).
[[nodiscard]] result<noise_analysis> analyse_noise(const phase_source& x, double level,
                                                   const tau_range& range = {},
                                                   const noise_series& series = {},
                                                   const progress_fn& on_progress = {});

}  // namespace gyroflip::analysis
