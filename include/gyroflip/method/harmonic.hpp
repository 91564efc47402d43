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
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/result.hpp"
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

struct harmonic_options {
  int harmonics = 1;  ///< 1: b, c1, s1; 2: also c2, s2
  /// A table of two positions 180 deg apart (0/180): fit b and the projection p1 of the first
  /// harmonic on the first position's direction, r = b + p1 cos(theta - theta_0) (names "b",
  /// "p1"); a block then spans whole visiting periods until it has a residual degree of freedom
  /// (A, B, A, B for the paper's cycle). Otherwise two positions are refused.
  bool projection_of_two = false;
};

/// The fitted terms, in the order b (the blocks' mean bias), c1, s1[, c2, s2] (deg/s).
struct harmonic_fit {
  std::vector<std::string> names;  ///< "b", "c1", "s1"[, "c2", "s2"]
  std::vector<double> value;
  std::vector<double> covariance;  ///< row-major, names.size()^2 (see the file comment)
  std::size_t period = 0;          ///< dwells per block (the visiting period)
  std::size_t blocks = 0;          ///< complete blocks fitted
  std::size_t skipped_dwells = 0;  ///< dwells outside the pattern (after a gap): left out
  std::size_t dwells = 0;          ///< dwells in the blocks fitted
  double block_s = 0.0;  ///< mean block length (s): first to last block's start / (blocks - 1)
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

/// Fits the harmonics to `dwells` (time order) of a table of `table` (its angles). Errors: fewer
/// than 3 positions for one harmonic (5 for two), positions whose harmonics cannot be told
/// apart (rank-deficient block design), fewer than 3 complete blocks.
[[nodiscard]] result<harmonic_fit> fit_harmonics(std::span<const indexed_dwell> dwells,
                                                 const position_table& table,
                                                 const harmonic_options& options = {});

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
