/// \file
/// \brief The harmonic fit of an indexed run (issue 33): dwell means at N table positions as
///   r_k = b + c1 cos(theta_k) + s1 sin(theta_k) [+ c2 cos(2 theta_k) + s2 sin(2 theta_k)]
/// with the covariance of the terms from the data's own scatter, and the heading (north
/// finding) it gives with a vertical table axis. docs/NORTH.md derives it.
///
/// Estimator: the run's dwells fall into blocks of one visiting period P (the smallest period of
/// the dwells' position sequence, e.g. 8 for the sweep 0,1,2,3,3,2,1,0). Each block is fitted
/// by ordinary least squares with its own bias and bias slope,
///   r_k = b_j + b'_j (t_k - t_j) + sum_h (c_h cos(h theta_k) + s_h sin(h theta_k)),
/// so a bias that moves linearly within a block drops out (for a sweep the slope column is
/// orthogonal to the harmonics and costs them nothing). The run's terms are the blocks' mean;
/// their covariance is the blocks' sample covariance over n blocks, each variance scaled to the
/// variance of the mean its block series' own overlapping Allan variance gives at n/32..n/8
/// blocks (so flicker and random walk of the bias are accounted for, docs/NORTH.md), never
/// taken from a sensor's specification.
///
/// Small, self-contained API (no file formats, no printing), to sit behind the method's
/// demodulator interface later.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/method/plan.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// One dwell of an indexed run: its mean time, position (an index of the table) and mean rate.
struct indexed_dwell {
  double time_s = 0.0;
  int position = 0;
  double rate_dps = 0.0;
  double weight = 1.0;  ///< conversions averaged (n_avg): the white noise's weight
};

/// The dwells of recording rows: each row at a position with n_avg > 1 is one dwell (a dwell
/// recording, a `.gfr`'s dwells); consecutive rows with n_avg 1 at one position (a raw
/// recording) are averaged into one. Rows taken while the table turns separate dwells.
[[nodiscard]] std::vector<indexed_dwell> indexed_dwells(std::span<const row> rows);

/// The terms a harmonic fit can hold, in their order: the bias b, then the first and second
/// harmonics' cos and sin terms (r(theta) = b + c1 cos theta + s1 sin theta + c2 cos 2 theta + s2
/// sin 2 theta).
inline constexpr std::array<std::string_view, 5> harmonic_term_names{"b", "c1", "s1", "c2", "s2"};

struct harmonic_options {
  int harmonics = 1;  ///< 1: b, c1, s1; 2: also c2, s2
  /// The harmonic terms to fit, a subset of c1, s1, c2, s2 in that order (b is always fitted);
  /// empty: those of `harmonics`. What a table separates: separability_of(table).estimable.
  std::vector<std::string> terms;
  /// Fit every term the table separates (separability_of(table).estimable) that a block of the
  /// visiting period has room for beside the bias and its slope (the last dropped until the
  /// block's design has full rank; harmonic_fit::dropped names them). Overrides the above.
  bool separable = false;
  /// A table of two positions 180 deg apart (0/180): fit b and the projection p1 of the first
  /// harmonic on the first position's direction, r = b + p1 cos(theta - theta_0) (names "b",
  /// "p1"); a block then spans whole visiting periods until it has a residual degree of freedom
  /// (A, B, A, B for the paper's cycle). Otherwise two positions are refused. Applies with
  /// `harmonics` 1 and neither `terms` nor `separable` (the design is then terms {"p1"}).
  bool projection_of_two = false;
};

/// The fitted terms, in the order b (the blocks' mean bias), c1, s1[, c2, s2] (deg/s).
struct harmonic_fit {
  std::vector<std::string> names;  ///< "b", "c1", "s1"[, "c2", "s2"] (or the terms; "b", "p1")
  std::vector<double> value;
  std::vector<double> covariance;  ///< row-major, names.size()^2 (see the file comment)
  std::size_t period = 0;          ///< dwells per block (the visiting period; p1: a multiple)
  std::size_t blocks = 0;          ///< complete blocks fitted
  std::size_t skipped_dwells = 0;  ///< dwells outside the pattern (after a gap): left out
  /// Terms the table separates that the visiting period had no room for (options.separable).
  std::vector<std::string> dropped;
  std::size_t dwells = 0;  ///< dwells in the blocks fitted
  double block_s = 0.0;    ///< mean block length (s): first to last block's start / (blocks - 1)
  /// The white noise of one dwell (deg/s), from the blocks' residuals (their rms, corrected for
  /// the parameters each block fits): N = this x sqrt(dwell length) when the bias is white.
  double dwell_sigma_dps = 0.0;
  /// Each term's standard error over its naive one (s / sqrt(n) of the blocks).
  std::vector<double> correlated_factor;
  /// Whether the correlated error (>= 32 blocks) or only the naive one was available.
  bool correlated = false;
  [[nodiscard]] double cov(std::size_t i, std::size_t j) const {
    return covariance[i * names.size() + j];
  }
  [[nodiscard]] double var(std::size_t i) const { return cov(i, i); }
};

/// The blocks of one visiting period a fit takes from `dwells` (time order): each block's first
/// dwell. The period is the smallest of the positions' sequence (2..16 dwells, checked over its
/// first four periods); after a dwell that breaks the pattern (a gap) the dwells are passed over
/// until the pattern starts again. Empty when no period is found.
struct harmonic_blocks {
  std::size_t period = 0;
  std::vector<std::size_t> starts;
};
[[nodiscard]] harmonic_blocks blocks_of(std::span<const indexed_dwell> dwells);

/// Fits the harmonics to `dwells` (time order) of a table of `table` (its angles). Errors: fewer
/// than 3 positions for one harmonic (5 for two), positions whose harmonics cannot be told
/// apart (rank-deficient block design), fewer than 3 complete blocks.
[[nodiscard]] result<harmonic_fit> fit_harmonics(std::span<const indexed_dwell> dwells,
                                                 const position_table& table,
                                                 const harmonic_options& options = {});

/// What the table's axis is, for what the terms mean physically (separability_of): `vertical`
/// (`up`/`down`: north finding), `horizontal` (any other, and a recording that names none: the
/// simulator's default axis, perpendicular to the sensitive axis and level, the paper's rig).
enum class table_axis_kind { horizontal, vertical };
/// The kind of a `# table_axis:` value (earth::parse_axis: within 8 deg of the vertical is
/// vertical); empty or unreadable: horizontal.
[[nodiscard]] table_axis_kind table_axis_kind_of(std::string_view table_axis_text);

/// Two things one run cannot tell apart: terms of the fit that the table's angles alias
/// ("c2" and "c1" at 0/120/240 deg), or physical quantities that enter the same term ("Earth
/// rate" and "g-sensitivity" in c1 and s1), with what would separate them (empty: nothing).
struct inseparable_pair {
  std::string first, second;
  std::string in_terms;      ///< the fitted term(s) that hold them
  std::string why;           ///< one line
  std::string separated_by;  ///< what separates them, or "nothing"
};
/// What a fitted term holds physically.
struct term_meaning {
  std::string term;
  std::string holds;
};
/// The separability report of an indexed run (issue 33 item 2): which terms the table's angles
/// separate, what each holds physically about this table axis, and every pair no run of this
/// kind separates. Written before a run (`calibrate --explain`) and with every result.
/// docs/METHOD-NOTES.md, "N-position indexing".
struct separability {
  std::string positions;  ///< the table's angles ("0, 90, 180, 270")
  std::string axis;       ///< "horizontal" or "vertical"
  /// Whether the axis was known (given, or recorded: `# table_axis:`); false: the recording does
  /// not say (an older `.gfr`, a CSV without the line) and `axis` is the horizontal taken.
  bool axis_recorded = true;
  std::vector<std::string> estimable;     ///< b first, then the harmonic terms separated
  std::vector<std::string> unobservable;  ///< terms whose regressor is zero at every angle
  std::vector<term_meaning> meanings;     ///< one per estimable term
  std::vector<inseparable_pair> pairs;    ///< every inseparable pair (design, then physics)
  /// The report as lines of text (no trailing newline), for a front end to print.
  [[nodiscard]] std::vector<std::string> lines() const;
};
/// The report for `table` (at least 3 positions for any harmonic; fewer: b and c1 only, and
/// says so) about a table axis of kind `axis`. Design: a term whose regressor over the table's
/// angles lies in the span of the terms before it (b, c1, s1, c2, s2 in that order) is not
/// estimable, and is named with each term it aliases onto (e.g. cos 2 theta = cos theta at
/// 0/120/240). Physics: the terms' meaning for a gyro whose sensitive axis is perpendicular to
/// the table axis (docs/METHOD-NOTES.md derives them).
[[nodiscard]] separability separability_of(const position_table& table, table_axis_kind axis);

/// The harmonic (N-position) demodulator, scheme `harmonic` (method/demodulator.hpp): dwells at
/// every table position, one estimate per visiting period (found from the first dwells, as
/// blocks_of), fitted as fit_harmonics fits a block (bias, bias slope and the terms the table
/// separates); its estimate's r is the block's c1 (the first harmonic's term at the table's 0
/// deg, which for 0/180 is the half-difference's), c its bias b. Errors: a table of fewer than 3
/// positions (naming `source`).
[[nodiscard]] result<std::unique_ptr<demodulator>> make_harmonic_demodulator(
    const position_table& table, const std::string& source);
/// The noise transfer of the harmonic demodulator for a visiting order of positions of `table`
/// (one period; equally spaced dwells): the c1 and b rows of the block's least-squares solution
/// (bias, slope and the terms separability_of gives, as fitted). The scheme's row of schemes()
/// states that of the four-position sweep 0, 90, 180, 270, 270, 180, 90, 0.
[[nodiscard]] result<noise_transfer> harmonic_transfer(const position_table& table,
                                                       std::span<const int> visiting_order);

/// The Cramer-Rao bound of a harmonic fit's terms other than b (docs/METHOD-NOTES.md, "The
/// Cramer-Rao bound of an N-position run"): dwell means of length `dwell_s` at the times and
/// positions of `dwells`, cut into blocks as `fit` was (blocks_of; p1: whole periods), each block
/// with its own bias and bias slope as nuisance parameters, and Gaussian noise whose dwell means
/// have the gap two-sample variance method::gap_avar(noise, dwell_s, spacing) (white, flicker and
/// random walk of the rate: Barnes 1971). The nuisance is removed by projecting each block onto the
/// contrasts orthogonal to its constant and slope (the restricted likelihood, whose Fisher
/// information of the terms equals the full model's Schur complement), where the noise's
/// covariance is a function of the structure function alone:
///   cov(sum_a u_a y_a, sum_b v_b y_b) = -sum_ab u_a v_b gap_avar(|t_a - t_b|)  (sum u = sum v = 0)
/// and the bound is the inverse of Z^T C^-1 Z (Z the projected regressors). Returns the
/// covariance bound of fit.names[1..] (row-major). Cost O(M^3), M = blocks x (period - 2).
[[nodiscard]] result<std::vector<double>> harmonic_crlb(const harmonic_fit& fit,
                                                        std::span<const indexed_dwell> dwells,
                                                        const position_table& table,
                                                        const plan_noise& noise, double dwell_s);
/// The same for any noise with stationary increments: `gap_avar(spacing_s)` is the gap
/// two-sample variance of two dwell means (all of one length) whose starts are `spacing_s` apart.
[[nodiscard]] result<std::vector<double>> harmonic_crlb(
    const harmonic_fit& fit, std::span<const indexed_dwell> dwells, const position_table& table,
    const std::function<double(double)>& gap_avar);

/// The gap two-sample variance of two means of length `tau_s` whose starts are `spacing_s` >=
/// tau_s apart, of a first-order Gauss-Markov process of variance `variance` and time constant
/// `time_constant_s` (autocovariance q e^{-|u|/T}): var - cov(S) with
///   var = 2 q (T/tau)^2 (tau/T - 1 + e^{-tau/T}),
///   cov(S) = q (T/tau)^2 e^{-S/T} (e^{tau/T} + e^{-tau/T} - 2)
/// (the double integrals of the autocovariance over the two intervals). A bank of them is the
/// simulator's flicker (sensor/error_terms.hpp), so its exact bound is a sum of these.
[[nodiscard]] double gauss_markov_gap_avar(double variance, double time_constant_s, double tau_s,
                                           double spacing_s) noexcept;

/// The azimuth (deg from north, clockwise) of the sensitive axis at the table's 0 deg from a
/// first harmonic (c1, s1) of the Earth rate about a vertical table axis. With the table axis
/// up (angles counter-clockwise seen from above) the axis at table angle theta points to
/// psi - theta, so r(theta) = W_H cos(psi - theta): psi = atan2(s1, c1); table axis down:
/// psi = atan2(-s1, c1). Its 1 sigma by the delta method from the covariance of (c1, s1), and
/// the horizontal Earth rate the fit implies, sqrt(c1^2 + s1^2) (scale-factor error included).
struct heading_estimate {
  double heading_deg = 0.0;    ///< [0, 360)
  double sigma_deg = 0.0;      ///< 1 sigma
  double amplitude_dps = 0.0;  ///< sqrt(c1^2 + s1^2)
};
[[nodiscard]] heading_estimate heading_of(double c1, double s1, double var_c1, double var_s1,
                                          double cov_c1_s1, bool table_axis_up = true);

/// The heading from the projection p1 = W_H cos(psi - theta_0) of a 0/180 run (table axis up;
/// down: cos(psi + theta_0)) with the scale factor known: psi = theta_0 +- acos(p1 / W_H), the
/// sign not known from one such run (docs/NORTH.md). `heading_deg` is the solution with
/// psi - theta_0 in [0, 180] (up), `mirror_deg` the other. The 1 sigma by the delta method,
/// sigma_p / (W_H |sin(psi - theta_0)|), which grows without bound towards 0 and 180 deg: within
/// one sigma of the edge (|p1| > W_H - sigma_p, `at_edge`) it is the angle acos(1 - sigma_p/W_H)
/// instead.
struct projection_heading {
  double heading_deg = 0.0, mirror_deg = 0.0;
  double sigma_deg = 0.0;
  double cos_value = 0.0;  ///< p1 / W_H (may exceed 1 in magnitude with noise)
  bool at_edge = false;
};
[[nodiscard]] projection_heading heading_of_projection(double p1, double var_p1,
                                                       double earth_horizontal_dps,
                                                       double axis_angle_deg,
                                                       bool table_axis_up = true);

/// Two 0/180 runs at base azimuths `base_turn_deg` apart (the second's sensitive axis at table 0
/// turned clockwise by it), both with the pair's first position at `axis_angle_deg`, with the
/// scale factor known (docs/NORTH.md, "Two 0/180 runs"): their projections
///   p1 = W_H cos(phi) + g,  p2 = W_H cos(phi + turn) + g,  phi = psi - theta_0 (axis up; down:
///   psi + theta_0),
/// where g is the table's term (tilt x g-sensitivity, fixed to the table, so the same in both:
/// its projection on the axis at theta_0). Their difference removes g:
///   p1 - p2 = 2 W_H sin(turn / 2) sin(phi + turn / 2),
/// so phi = 180 - turn/2 - asin(x) (`heading_deg`) or asin(x) - turn/2 (`mirror_deg`),
/// x = (p1 - p2) / (2 W_H sin(turn/2)): still two solutions, mirror images about the direction
/// 90 - turn/2 from theta_0 (for turn = 180 the one run's pair, psi = theta_0 +- acos(x)). The 1
/// sigma by the delta method, sigma_x / sqrt(1 - x^2) (var p1 + var p2; the runs independent),
/// at the edge (|x| > 1 - sigma_x) acos(1 - sigma_x) as for one run. `table_term_dps` is g of
/// the heading_deg solution (p1 - W_H cos phi), `table_term_mirror_dps` the mirror's. Errors: a
/// turn within 1 deg of 0 or 360 (the difference holds no Earth rate).
struct two_projection_heading {
  projection_heading heading;
  double table_term_dps = 0.0, table_term_mirror_dps = 0.0;
};
[[nodiscard]] result<two_projection_heading> heading_of_two_projections(
    double p1, double var_p1, double p2, double var_p2, double earth_horizontal_dps,
    double axis_angle_deg, double base_turn_deg, bool table_axis_up = true);

/// The white-noise limit of a heading (docs/NORTH.md): sigma_psi = k N / (W_E cos(lat) sqrt(T))
/// rad, N the angle random walk (deg/s/sqrt(Hz)), T the run (s), k = sqrt(2) for one gyro whose
/// bias is unknown (>= 3 positions), 1 for a pair whose bias is known. Returned in deg.
[[nodiscard]] double heading_white_limit_deg(double arw_dps_rthz, double lat_deg, double run_s,
                                             double k = 1.4142135623730951);
/// With dead time d (s) per dwell and the bias instability B (deg/s), at the best dwell
/// (docs/PLANNER.md): sigma_psi = k (N + 0.664 B sqrt(d)) / (W_E cos(lat) sqrt(T)), in deg.
[[nodiscard]] double heading_dead_time_limit_deg(double arw_dps_rthz, double bias_instability_dps,
                                                 double dead_time_s, double lat_deg, double run_s,
                                                 double k = 1.4142135623730951);

/// Two runs at base azimuths differing by `base_turn_deg` (the second's sensitive axis at
/// table 0 turned by it, clockwise), each's first harmonic (c1, s1) with its 2x2 covariance
/// (row-major): the first run's heading with a term fixed to the table (the table's tilt x
/// g-sensitivity, docs/NORTH.md) removed. With the Earth's part E e^{i psi} and the table's G:
/// h1 = E u(psi) + G, h2 = E u(psi + turn) + G, so h1 - h2 = E u(psi) (1 - u(turn)) (complex,
/// u(a) = cos a + i sin a, sign per the table axis) and psi = arg((h1 - h2) / (1 - u(turn))).
/// Also the table's term G (deg/s, its magnitude) and 1 sigma of the heading.
struct two_azimuth_heading {
  heading_estimate first;       ///< the first run's heading, table term removed
  double table_term_dps = 0.0;  ///< |G|
  double table_term_c1_dps = 0.0, table_term_s1_dps = 0.0;
};
[[nodiscard]] result<two_azimuth_heading> heading_two_azimuths(
    std::array<double, 2> h1, std::array<double, 4> cov1, std::array<double, 2> h2,
    std::array<double, 4> cov2, double base_turn_deg, bool table_axis_up = true);

}  // namespace gyroflip::method
