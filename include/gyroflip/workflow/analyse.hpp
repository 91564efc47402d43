/// \file
/// \brief The analysis of one run (module workflow): its calibration by the chosen pairing, the
/// pairing comparison (the paper's simple pairing against abba), the compensated rate and the
/// noise of the raw sensor and of the compensated rate (OADEV with bounds, the IEEE 952 terms).
/// What `gyroflip report` shows per run.
#pragma once

#include <optional>
#include <vector>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/delta_n_model.hpp"
#include "gyroflip/workflow/compensate.hpp"
#include "gyroflip/workflow/recordings.hpp"

namespace gyroflip::workflow {

/// One pairing's per-cycle statistics of a run.
struct pairing_stats {
  method::pairing pairing = method::pairing::simple;
  method::calibration cal;  ///< dN, per-cycle std, correlated standard error
  /// OADEV of the cycle values at the longest tau both pairings reach (empty when too short).
  std::optional<analysis::deviation_point> oadev_at_common_tau;
};

/// Windows (s) at which a run's drift (range of the moving mean, the paper's metric) is given
/// raw beside compensated: each that fits at least twice into the run.
inline constexpr double drift_windows_s[] = {100.0, 1000.0};

/// The range of the moving mean over `window_s` of the raw sensor (0 deg dwell means) and of
/// the compensated rate (deg/s).
struct drift_pair {
  double window_s = 0.0;
  double raw_dps = 0.0;
  double comp_dps = 0.0;
};

struct run_analysis {
  recording_run run;
  method::pairing pairing = method::pairing::abba;
  method::calibration cal;              ///< of the chosen pairing's cycles (a stationary run's dN)
  std::vector<pairing_stats> pairings;  ///< simple (the paper's), then abba
  compensation comp;                    ///< after compensate_run
  /// The raw sensor (its dwell means at 0 deg, one per cycle: what a sensor that is not flipped
  /// gives) and the compensated rate: OADEV with 68.3 % bounds and, when the series is long
  /// enough, the IEEE 952 terms (noise_fitted); empty when too short for a deviation.
  std::optional<analysis::noise_analysis> raw_noise, comp_noise;
  /// The share of the raw series' spacing its dwell means average (median dwell data span over
  /// the mean spacing of the 0-deg dwells; the rest is turning and settling); 0 when unknown.
  /// White rate noise averaged over a share d of each spacing tau0 looks, at tau0 and beyond,
  /// like white noise of N / sqrt(d): the sensor's own N is the fitted N times sqrt(d).
  double raw_duty = 0.0;
  std::vector<drift_pair> drifts;  ///< after compensate_run, at drift_windows_s
};

/// True when `a` holds fitted IEEE 952 terms (not only the deviation curve).
[[nodiscard]] bool noise_fitted(const analysis::noise_analysis& a) noexcept;

/// `a`'s IEEE 952 terms when fitted (noise_fitted), else nothing: what an Allan plot draws.
[[nodiscard]] std::optional<analysis::noise_terms> fitted_terms(const analysis::noise_analysis& a);

/// Calibrates the run with pairing `p` and compares the pairings. Errors: too few cycles.
[[nodiscard]] result<run_analysis> analyse_run(recording_run run, method::pairing p);

/// Compensates the analysed run with `model` (compensate_cycles) and analyses the noise.
/// Errors: those of compensate_cycles.
[[nodiscard]] status compensate_run(run_analysis& a, const method::delta_n_model& model);

}  // namespace gyroflip::workflow
