/// \file
/// \brief The flip-period planner: the dwell that minimises the error of a run's compensated
/// rate for a given dead time, from the gap two-sample variance of the sensor's noise.
///
/// A two-position run alternates dwells of length tau between the positions; each turn costs
/// the dead time d (turn + settle: no data), so dwells start S = tau + d apart. Over a run the
/// compensated rate is (mean of the A dwells - mean of the B dwells)/2 (abba and the simple
/// pairing give it alike but for the run's two edge dwells: docs/PLANNER.md), so its error is a
/// sum of differences of dwell means. For noise with stationary increments, the covariance of
/// such differences is a function of the gap two-sample variance sigma^2(tau, T) alone (Barnes
/// et al. 1971, NBS TN 394; its bias functions B2 and B3 in NIST TN 1318, D.A. Howe et al.
/// 1981), which has closed forms for the IEEE 952 terms (docs/PLANNER.md derives them):
///   white PM (Q):   2 Q^2/tau^2 (T > tau; 3 Q^2/tau^2 at T = tau)
///   white FM (N):   N^2/tau
///   flicker FM (B): B^2/(2 pi) [(r+1)^2 ln(r+1) + (r-1)^2 ln(r-1) - 2 r^2 ln r],  r = T/tau
///   random walk FM (K): K^2 (3T - tau)/6
/// The rate ramp R is left out: abba cancels it (a ramp is a bias, not a noise, for the planner).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::method {

/// The IEEE 952 noise terms the planner uses, in analysis::noise_terms' base units: Q deg,
/// N deg/s/sqrt(Hz) (IEEE, two-sided), B deg/s (the flicker coefficient: ADEV floor 0.664 B),
/// K deg/s/sqrt(s).
struct plan_noise {
  double quantization_deg = 0.0;
  double arw_dps_rthz = 0.0;
  double bias_instability_dps = 0.0;
  double rrw_dps_per_rts = 0.0;
};

/// The two-sample variance ((deg/s)^2) of two dwell means of length `tau_s` whose starts are
/// `spacing_s` >= tau_s apart, for the noise `n` (Barnes 1971 with the closed forms above).
[[nodiscard]] double gap_avar(const plan_noise& n, double tau_s, double spacing_s) noexcept;

/// The variance ((deg/s)^2) of the compensated rate of a run of `pairs` A/B dwell pairs, each
/// dwell `tau_s` long and the next one `tau_s + dead_s` later: the pairs' own variance
/// gap_avar(tau, S)/(2 pairs) plus the covariance between pairs (non-zero for flicker only; a
/// second difference of gap_avar). Exact for noise with stationary increments (docs/PLANNER.md).
[[nodiscard]] double flip_mean_variance(const plan_noise& n, double tau_s, double dead_s,
                                        std::size_t pairs) noexcept;

/// The pairs a run of `duration_s` holds: floor(duration / (2 (tau + dead))).
[[nodiscard]] std::size_t pairs_in(double duration_s, double tau_s, double dead_s) noexcept;

/// The white + flicker approximation (independent pairs, the flicker pair variance 0.4413 B^2):
/// tau* = sqrt(d tau_c), tau_c = N^2 / (0.4413 B^2), sigma* = (N + 0.664 B sqrt(d)) / sqrt(T).
struct flip_plan_closed_form {
  double corner_tau_s = 0.0;  ///< tau_c: where white and flicker contribute alike (s)
  double dwell_s = 0.0;       ///< tau* (s)
  double sigma_dps = 0.0;     ///< sigma* for the run (deg/s)
};
[[nodiscard]] flip_plan_closed_form plan_flip_closed_form(const plan_noise& n, double dead_s,
                                                          double duration_s) noexcept;

/// One point of a planner's curve.
struct plan_point {
  double x = 0.0;          ///< the dwell (s) or the run length (s)
  double sigma_dps = 0.0;  ///< predicted 1-sigma error of the compensated rate (deg/s)
};

/// What plan_flip finds.
struct flip_plan {
  double dwell_s = 0.0;     ///< tau*: the dwell that minimises the error
  double dead_s = 0.0;      ///< the dead time per turn it was planned for
  double period_s = 0.0;    ///< the A/B cycle: 2 (tau* + d)
  double duration_s = 0.0;  ///< the run length planned for
  double sigma_dps = 0.0;   ///< the predicted error of the run's compensated rate at tau*
  /// The same for a run without dead time at tau* (what the dead time costs: sigma/this).
  double sigma_no_dead_dps = 0.0;
  flip_plan_closed_form closed_form;    ///< the white + flicker approximation, for comparison
  std::vector<plan_point> by_dwell;     ///< sigma against the dwell, for `duration_s`
  std::vector<plan_point> by_duration;  ///< sigma at tau* against the run length
};

/// Limits of the search.
struct plan_limits {
  double min_dwell_s = 0.01;  ///< shortest dwell considered (s, > 0)
  /// longest dwell considered (s); 0: a quarter of the run (at least two pairs)
  double max_dwell_s = 0.0;
  std::size_t curve_points = 61;  ///< points of by_dwell (log-spaced)
};

/// The dwell in [limits] that minimises flip_mean_variance for a run of `duration_s` with
/// `dead_s` per turn (a log-spaced scan, then golden-section refinement). Errors: no noise,
/// negative or non-finite inputs, a run too short for two pairs at the shortest dwell.
[[nodiscard]] result<flip_plan> plan_flip(const plan_noise& n, double dead_s, double duration_s,
                                          const plan_limits& limits = {});

}  // namespace gyroflip::method

namespace gyroflip::method {

/// One visiting period of an indexed run of three or more positions (issue 33, docs/PLANNER.md
/// "More positions"): the dwells' angles in visiting order (the sweep 0, 90, 180, 270, 270, 180,
/// 90, 0), each dwell `tau_s` long, a turn of `dead_s` (turn + settle) between dwells at
/// different angles and none between two at the same angle, and the weights of the first
/// harmonic's estimate per period: the least-squares fit of b + b' t + c1 cos + s1 sin to the
/// period's dwell means (method/harmonic.hpp's estimator), c1 = sum_k weight_c[k] mean_k.
struct indexed_period {
  std::vector<double> visit_deg;           ///< the dwells' angles, one period
  double dwell_s = 0.0;                    ///< each dwell's length
  std::vector<double> start_s;             ///< each dwell's start within the period
  double period_s = 0.0;                   ///< from one period's first dwell start to the next's
  std::vector<double> weight_c, weight_s;  ///< c1 and s1 per dwell mean
};

/// The period of dwells `tau_s` long at `visit_deg` with `dead_s` per turn (the turn from the
/// last dwell back to the first counted when their angles differ). Errors: fewer than three
/// distinct angles, or angles whose first harmonic the period cannot separate from a bias and
/// its slope (a rank-deficient design).
[[nodiscard]] result<indexed_period> indexed_period_of(std::span<const double> visit_deg,
                                                       double tau_s, double dead_s);

/// The drift-cancelling visiting order of distinct angles: forwards then backwards, each end
/// dwelt twice (as rig::sweep_order, which the simulator visits by default).
[[nodiscard]] std::vector<double> sweep_visits(std::span<const double> angles_deg);

/// The covariance ((deg/s)^2) of the run's first harmonic (c1, s1): the mean over `periods`
/// consecutive periods of each period's estimate. Exact for noise with stationary increments:
/// Var(sum w_j mean_j) = -1/2 sum_jk w_j w_k D(|t_j - t_k|), D(s) = 2 gap_avar(tau, s), because
/// each period's weights sum to zero (docs/PLANNER.md, "More positions").
struct harmonic_variance {
  double var_c1 = 0.0, var_s1 = 0.0, cov = 0.0;
  /// (var_c1 + var_s1)/2: the first harmonic's variance per component, averaged over the
  /// heading (the heading's variance is this / W_H^2 for any true heading when var_c1 = var_s1
  /// and cov = 0, as for equally spaced positions).
  [[nodiscard]] double mean_var() const noexcept { return 0.5 * (var_c1 + var_s1); }
};
[[nodiscard]] harmonic_variance indexed_run_variance(const plan_noise& n, const indexed_period& p,
                                                     std::size_t periods) noexcept;

/// The dwell in [limits] that minimises the first harmonic's error (harmonic_variance::mean_var)
/// of an indexed run of `duration_s` visiting `visit_deg` over and over, `dead_s` per turn (the
/// same search as plan_flip). In the result sigma_dps is sqrt(mean_var), period_s one visiting
/// period at the planned dwell, closed_form the two-position closed form (for reference).
/// Errors: those of plan_flip and indexed_period_of; a run too short for 3 periods.
[[nodiscard]] result<flip_plan> plan_indexed(const plan_noise& n, std::span<const double> visit_deg,
                                             double dead_s, double duration_s,
                                             const plan_limits& limits = {});

}  // namespace gyroflip::method
