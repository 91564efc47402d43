/// \file
/// \brief Is a calibration run stationary? The one test `calibrate`, `report`, Python and the
/// recorder use before a run's mean r is called the sensor's dN (paper eqns 8-11 hold only for
/// w_in = 0). Three statistics, each against a stated limit (docs/METHOD-NOTES.md,
/// "Stationarity"):
///
/// - **scatter**: the per-cycle std of r against the white noise of the same dwells, read from
///   the half-sum c at the shortest averaging time (an input rate enters r, not c; the bias
///   enters c, not r). Under white dwell noise r's and c's noise have one distribution whatever
///   the pairing (each is the same linear combination of the dwells, with signs), so
///   std(r) / ADEV_c(tau0) is the pairing's white-noise ratio (`white_std_over_adev`).
/// - **drift or step**: three statistics on r, each scaled by r's long-run std at short averaging
///   times (AVAR at m = min(16, n/8) cycles times m, robust to a step or a ramp), each with a
///   limit whose asymptotic false-alarm rate is stated. A failure also needs the level change to
///   exceed the run's own correlated error (noise the stated error of dN already covers is not
///   called a drift).
///   - the **step statistic**: the largest standardized mean difference before and after a split,
///     max_k |S_k| / (sigma_LR sqrt(k (n - k) / n)) over splits at least `step_trim_cycles`
///     from either end (the sup-t, square root of Andrews' 1993 sup-F, Econometrica 61(4)
///     821-856, for one mean; Csorgo & Horvath 1997, Limit Theorems in Change-Point Analysis,
///     ch. 1): it sees a step wherever it lies, also in a run's first or last minute, which the
///     CUSUM below weighs by k (n - k) / n and misses (fifth review of issue 31, F1);
///   - the **slope statistic**: the t of r's least-squares slope in time with the long-run
///     variance (a ramp: 2.3 times the CUSUM's power; fifth review, F2);
///   - the OLS-CUSUM of before (Ploberger and Kramer 1992, Econometrica 60(2) 271-285),
///     max_k |S_k| / (sigma_LR sqrt(n)), still written and judged (a run it refused stays
///     refused).
/// - **g-term**: the g-term (dN less the Earth rate; without a geometry at least |dN| - W_E)
///   against what the sensor's specification allows at 1 g (a guaranteed maximum, or three times a
///   typical value), less three correlated errors. Without a specification it is not checked, and
///   then a constant input of any size passes: such a run is not vouched for (`vouched`), its
///   caller warns (`caveats`) and a strict caller refuses it.
/// - **temperature**: a run whose temperature moves more than isothermal_span_c is not
///   isothermal: its dN is a mean over temperatures that no dN(T) can place (the one rule of
///   `calibrate` and `report`).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// std(r) / ADEV_r(tau0) of a pairing's cycle series under white dwell noise: its scheme's noise
/// transfer (method/demodulator.hpp, noise_transfer::white_std_over_adev): simple 1; abba
/// sqrt(20/14) = 1.195 (interior cycles: r = (3 z_a + 3 z_b + z_prev + z_next)/8, var 20/64,
/// lag-1 covariance 6/64; docs/METHOD-NOTES.md).
[[nodiscard]] double white_std_over_adev(pairing p) noexcept;

/// Fewest cycles the test runs on (fewer: `checked` false).
inline constexpr std::size_t min_stationarity_cycles = 16;

/// Limit of the drift statistic: P(sup|Brownian bridge| > 2.4) = 2e-5 asymptotically; measured
/// on white cycle series with the long-run std estimated (bench/stationarity_null.py): at most
/// 7e-4 for 40 to 5000 cycles, either pairing.
inline constexpr double drift_limit = 2.4;

/// Averaging factor (cycles) of the long-run std that scales the drift statistic: long enough
/// for abba's lag-1 correlation, short enough that a drift or step barely enters it.
inline constexpr std::size_t drift_scale_cycles = 16;

/// Asymptotic false-alarm rate of each of the step and slope statistics on a stationary run
/// (their limits: step_statistic_limit, slope_statistic_limit). Measured on the simulator's
/// still runs in bench/stationarity_null.py (docs/PERFORMANCE.md, "Issue 31").
inline constexpr double drift_false_alarm = 1e-4;

/// The step statistic's splits leave at least this many cycles (14 s of the paper's 1.79 s
/// cycle) on either side (fewer in runs under 32 cycles: n/4): a shorter segment's mean rests on
/// too few cycles for r's correlation at short lags.
inline constexpr std::size_t step_trim_cycles = 8;

/// P(sup |B(t)| / sqrt(t (1 - t)) > x) over t in [pi0, 1 - pi0], B a Brownian bridge: the
/// tail approximation x phi(x) (L (1 - 1/x^2) + 4/x^2), L = 2 ln((1 - pi0) / pi0) (James, James
/// & Siegmund 1987, Biometrika 74(1) 71-83; Csorgo & Horvath 1997, section 1.3; it gives
/// Andrews' 1993 Table I critical values for one parameter, sup-F 8.85 at 5 % with pi0 = 0.15,
/// docs/FACTS.md). Valid in the tail (x above ~2).
[[nodiscard]] double sup_t_tail(double x, double pi0) noexcept;

/// Limit of the step statistic for n cycles, trim cycles at either end and a long-run variance
/// with `edf` degrees of freedom: the x with sup_t_tail(x, trim/n) = drift_false_alarm, taken to
/// Student's t with `edf` degrees of freedom at the same tail probability (the long-run variance
/// is an estimate: from 40 cycles it has ~9 degrees of freedom, from 1000 ~90).
[[nodiscard]] double step_statistic_limit(std::size_t n, std::size_t trim, double edf);

/// Limit of the slope statistic: Student's t with `edf` degrees of freedom at the two-sided
/// probability drift_false_alarm (3.89 for infinitely many).
[[nodiscard]] double slope_statistic_limit(double edf);

/// A run whose temperature moves more than this (degC) is not isothermal (review R17): its dN is
/// a mean over temperatures no dN(T) sees; the HZ1's dN moves 9e-5 deg/s over 2 degC (paper Tab.
/// 3), about a 1-h run's within-run error.
inline constexpr double isothermal_span_c = 2.0;

/// The specification the g-term is checked against (deg/s at 1 g): a guaranteed maximum, or a
/// typical value (then the limit is `typical_factor` times it: a unit at twice its datasheet's
/// typical value is not unusual, the paper's ADXRS150 is). No limit: the g-term is not checked.
struct g_term_spec {
  double max_dps = 0.0;  ///< guaranteed maximum at 1 g (0: none)
  double typ_dps = 0.0;  ///< typical at 1 g (0: none)
  std::string source;    ///< where the figure comes from, for messages
  static constexpr double typical_factor = 3.0;
  [[nodiscard]] double limit_dps() const noexcept {
    return max_dps > 0.0 ? max_dps : typical_factor * typ_dps;
  }
};

/// The sensor's white noise the run's scatter is held against (issue 31, fifth review F11): a
/// run whose r scatters far beyond what its specification's noise gives for these dwells is not
/// a calibration, even when its own half-sum c scatters as much (a knock, a broadband
/// disturbance). The dwells' averaging time is taken as the cycle's share (the cycle period over
/// its dwells), an upper bound (turns and settling are dead time), so a still run reads above 1
/// (HZ1 and ADXRS150 at 256 conversions: 1.3-1.5); hence the generous limit.
struct noise_spec {
  double arw_dps_rthz = 0.0;  ///< N: ADEV(tau) = N / sqrt(tau)
  std::string source;         ///< where the figure comes from, for messages
};

/// Limit of std(r) against the specification's white noise for the dwells (noise_spec):
/// still simulated runs read at most 1.6 (bench/stationarity_null.py, docs/PERFORMANCE.md); a run
/// four times noisier than its part is not a calibration of it.
inline constexpr double noise_ratio_limit = 4.0;

/// The outlier test's family-wise false-alarm rate: one cycle's |r - median| / (1.4826 MAD)
/// against the normal quantile of alpha / (2 n) (Bonferroni over the n cycles), and never below
/// outlier_floor_z (the MAD's own scatter at small n).
inline constexpr double outlier_alpha = 1e-4;
inline constexpr double outlier_floor_z = 5.0;

/// The outlier limit for n cycles (outlier_alpha, outlier_floor_z).
[[nodiscard]] double outlier_limit_z(std::size_t n) noexcept;

/// What the test needs besides the cycles.
struct stationarity_inputs {
  pairing pair = pairing::abba;
  std::optional<g_term_spec> spec;  ///< none: the g-term is not checked
  std::optional<noise_spec> noise;  ///< none: the scatter is held against c's only
  /// The geometry (latitude, sensitive axis at 0 deg): the g-term exactly; none: at least
  /// |dN| - W_E (any axis).
  std::optional<double> lat_deg;
  std::optional<earth::ned_vector> axis;
};

/// The test's statistics and verdicts. Every statistic is finite when `checked`.
struct stationarity {
  /// false: scatter and drift not tested (too few cycles, why_not says so) or a file that
  /// predates the test. The g-term and the temperature need no minimum: a short run has them.
  bool checked = false;
  std::string why_not;         ///< why scatter and drift were not checked
  std::size_t cycles = 0;      ///< cycles tested
  double scatter_ratio = 0.0;  ///< std(r) / (white_std_over_adev x ADEV_c(tau0)); ~1 stationary
  double scatter_limit = 0.0;  ///< max(1.25, 1 + 7/sqrt(n)) (null sd ~1.1/sqrt(n), measured)
  /// The lower limit, 0.75 (1 - 3/sqrt(n)): an input alternating with the turns (a vibration
  /// near the cycle's harmonics) enters the half-sum c, the noise reference, and drives the
  /// ratio far below 1; the bias's flicker lowers it a little (stationary runs: >= 0.58 at 67
  /// cycles, >= 0.86 at 3000, measured).
  double scatter_low_limit = 0.0;
  double temp_span_c = 0.0;      ///< the run's temperature range (0 without temperatures)
  double drift_statistic = 0.0;  ///< the OLS-CUSUM max_k |S_k| / (sigma_LR sqrt(n)), r - mean
  double drift_limit_value = drift_limit;
  /// Mean of r after the step statistic's split less before it (files before it: the CUSUM's).
  double step_dps = 0.0;
  double step_time_s = 0.0;     ///< time of the split (the cycle after it)
  double step_limit_dps = 0.0;  ///< 3 x the run's correlated error of dN
  /// The step statistic (sup-t, see the file comment) and its limit; 0 and 0 in files written
  /// before it (not judged).
  double step_statistic = 0.0;
  double step_statistic_limit_value = 0.0;
  std::size_t trim_cycles = 0;  ///< cycles the step statistic's splits leave at either end
  /// The slope statistic (t of r's slope in time, signed) and its limit; 0 and 0 before it.
  double slope_statistic = 0.0;
  double slope_limit = 0.0;
  double ramp_dps = 0.0;          ///< r's fitted change from the first cycle to the last
  double long_run_std_dps = 0.0;  ///< sigma_LR of one cycle's r (the statistics' scale)
  /// What the test cannot see in this run: the step at mid-run, the step 3 % from either end and
  /// the ramp over the run that reach their statistic's limit (each caught half of the time at
  /// that size; smaller ones pass and stay in dN). 0 in files written before them.
  double step_hidden_dps = 0.0;
  double step_hidden_end_dps = 0.0;
  double ramp_hidden_dps = 0.0;
  bool g_checked = false;     ///< a specification was given
  bool g_exact = false;       ///< the geometry was given (else a lower bound)
  double g_term_dps = 0.0;    ///< |g-term| (or its lower bound)
  double g_limit_dps = 0.0;   ///< the specification's limit at 1 g
  double g_margin_dps = 0.0;  ///< 3 x the correlated error, taken off the g-term first
  std::string g_source;
  bool has_temp = true;        ///< the run has temperatures (false: temperature not checked)
  bool noise_checked = false;  ///< a noise specification was given (noise_spec)
  double noise_ratio = 0.0;    ///< std(r) / the specification's white std for these dwells
  double noise_limit = noise_ratio_limit;
  std::string noise_source;
  double outlier_z = 0.0;         ///< max |r - median| / (1.4826 MAD) over the cycles
  double outlier_limit = 0.0;     ///< outlier_limit_z(cycles)
  std::size_t outlier_cycle = 0;  ///< the cycle (from 1) of the largest
  double outlier_time_s = 0.0;    ///< its time
  bool scatter_failed = false;
  bool drift_failed = false;
  bool g_failed = false;
  bool temp_failed = false;  ///< temp_span_c > isothermal_span_c
  bool noise_failed = false;
  bool outlier_failed = false;
  /// A statistic failed: scatter, drift, noise and outlier need `checked`; the g-term and the
  /// temperature are judged on a run of any length.
  [[nodiscard]] bool failed() const noexcept {
    return (checked && (scatter_failed || drift_failed || noise_failed || outlier_failed)) ||
           g_failed || temp_failed;
  }
  /// Passed every statistic, the g-term included: a run whose g-term was not checked passed the
  /// scatter and drift tests only, which a constant input of any size passes; a run too short
  /// for the scatter and drift tests is not vouched for either.
  [[nodiscard]] bool vouched() const noexcept { return checked && !failed() && g_checked; }
  /// One sentence per failed statistic, with its value and limit (empty when none failed).
  [[nodiscard]] std::vector<std::string> failures() const;
  /// What limits a run that did not fail: its g-term not checked (empty when vouched or failed).
  [[nodiscard]] std::vector<std::string> caveats() const;
  /// The verdicts judged again from the statistics (a file's stored verdicts may have been edited:
  /// `calibrate` wrote them from these statistics, with these limits).
  [[nodiscard]] stationarity rejudged() const;
  /// The drift verdict from the statistics: the CUSUM, the step or the slope statistic beyond its
  /// limit (the last two judged when their limit is written), with the level change beyond
  /// step_limit_dps.
  [[nodiscard]] bool drift_judged_failed() const noexcept;
  /// One line: "stationary (scatter 0.96 <= 1.25, drift 0.7 <= 2.4, step 2.9 <= 5.3, slope 1.1
  /// <= 4.2, g-term ...)" or the failures.
  [[nodiscard]] std::string summary() const;
};

/// The cycle count of a growing run's next test after one at `n_cycles` (the recorder's live
/// check): first_live_look_cycles, then 25 % more each time. A test at every new cycle would
/// make the run's false-alarm rate grow with its length; looks spaced geometrically make it
/// grow with its logarithm (about 40 looks in a 3-day run; measured in bench/stationarity_null.py
/// --looks, docs/PERFORMANCE.md).
/// The recorder's first look: the drift limit is calibrated from 40 cycles on (below, the
/// long-run std rests on averages of 2-4 cycles and the statistic's tail is heavier: looks at 20
/// cycles gave 2 % false alarms on cold HZ1 runs, bench/stationarity_null.py --looks).
inline constexpr std::size_t first_live_look_cycles = 40;

[[nodiscard]] std::size_t next_stationarity_look(std::size_t n_cycles) noexcept;

/// The stationarity test of one calibration run (see the file comment) from its cycles and their
/// calibration (`calibrate(cycles)`). Total: fewer than min_stationarity_cycles gives
/// `checked` false (the g-term and the temperature are still judged). Used by `gyroflip calibrate`,
/// `report`, Python's `calibrate` and `record`.
[[nodiscard]] stationarity check_stationarity(std::span<const cycle> cycles, const calibration& cal,
                                              const stationarity_inputs& in);

}  // namespace gyroflip::method
