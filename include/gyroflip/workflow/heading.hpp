/// \file
/// \brief North finding (issue 33): the azimuth of the sensitive axis at the table's 0 deg from
/// indexed runs about a vertical table axis, with its 1 sigma from the data's own noise and the
/// white-noise limit beside it (method/harmonic.hpp; docs/NORTH.md). What `gyroflip heading` and
/// Python's `gyroflip.heading` run.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "gyroflip/core/result.hpp"
#include "gyroflip/method/harmonic.hpp"

namespace gyroflip::workflow {

struct heading_request {
  std::vector<std::string> runs;  ///< one recording, or two at different base azimuths
  double lat_deg = 0.0;           ///< the site's latitude (deg)
  /// Table axis up (angles counter-clockwise seen from above) or down; unset: the recordings'
  /// `# table_axis:` (up or down), else up.
  std::optional<bool> table_axis_up;
  /// Two runs: how far the rig's base was turned (clockwise, deg) from the first run to the
  /// second; unset: the difference of the runs' `# azimuth_deg:` (a simulation's).
  std::optional<double> base_turn_deg;
  /// A sensor preset or TOML (empty: none): its N and B give the dead-time bound beside the
  /// limit; the sigma never comes from it.
  std::string sensor;
  /// Harmonics fitted: 1 (b, c1, s1) or 2 (also c2, s2: at least 5 positions; docs/NORTH.md
  /// says when it is warranted).
  int harmonics = 1;
};

struct heading_run {
  std::string path;
  method::harmonic_fit fit;
  method::heading_estimate heading;  ///< this run's own (the table's term not removed)
  /// A 0/180 run: the heading from the projection with the scale factor known (heading holds
  /// the same heading and sigma).
  std::optional<method::projection_heading> projection;
  /// Two harmonics fitted: the heading's 1 sigma the same run gives with one (deg).
  std::optional<double> sigma_one_harmonic_deg;
  std::string positions;  ///< the table, "0, 90, 180 and 270"
  std::size_t n_positions = 0;
  double run_s = 0.0;             ///< first to last dwell time plus a dwell period
  double dwell_s = 0.0;           ///< one dwell's length (0: not known)
  double dead_per_dwell_s = 0.0;  ///< time per dwell not measuring (turns, settling)
  double arw_dps_rthz = 0.0;      ///< N from the dwells' white noise (0: dwell not known)
};

struct heading_result {
  std::vector<heading_run> runs;
  double heading_deg = 0.0;  ///< of the (first) run's sensitive axis at table 0, [0, 360)
  double sigma_deg = 0.0;    ///< 1 sigma, from the data
  std::string scheme;        ///< e.g. "4 positions (0, 90, 180 and 270 deg), period 8 dwells"
  bool two_azimuths = false;
  double base_turn_deg = 0.0;
  /// The white-noise limit sqrt(2) N / (W_E cos(lat) sqrt(T)) for the runs' total T and the
  /// data's own N (0 when N is not known), and sigma over it.
  double limit_deg = 0.0;
  double ratio_to_limit = 0.0;
  double arw_dps_rthz = 0.0;
  /// With a sensor: its dead-time bound sqrt(2) (N + 0.664 B sqrt(d)) / (W_H sqrt(T)).
  std::optional<double> dead_time_bound_deg;
  double earth_horizontal_dps = 0.0;  ///< W_E cos(lat)
  double amplitude_dps = 0.0;         ///< the first harmonic's size (Earth x scale factor [+ G])
  /// Two azimuths: the table's first-harmonic term removed (|G|, deg/s) and as a heading error
  /// a single run would have had (deg).
  double table_term_dps = 0.0;
  double table_term_heading_deg = 0.0;
  /// A 0/180 run: the heading is known up to its mirror about the table's 0 deg direction
  /// (psi or 2 theta_0 - psi): `mirror_deg` is the other solution.
  bool ambiguous = false;
  double mirror_deg = 0.0;
  /// Two harmonics: the second's amplitude sqrt(c2^2 + s2^2) and its 1 sigma (deg/s).
  double second_harmonic_dps = 0.0, second_harmonic_sigma_dps = 0.0;
  std::vector<std::string> caveats;
};

/// Reads the runs, fits each (method::fit_harmonics) and finds the heading. Errors: a run that
/// cannot be read, fewer than 3 positions, a latitude within 5 deg of a pole (no horizontal
/// Earth rate to find north by), more than two runs, two runs whose base turn is unknown or 0.
[[nodiscard]] result<heading_result> find_heading(const heading_request& request);

/// The heading as `gyroflip heading --json` prints it and `gyroflip.heading` returns it (schema
/// gyroflip.heading/1): heading_deg, sigma_deg, limit_deg, ratio_to_limit, arw_dps_rthz, scheme,
/// dead_time_bound_deg (null without a sensor), the runs with their fitted terms, caveats; with
/// two runs base_turn_deg, table_term_dps, table_term_heading_deg.
[[nodiscard]] nlohmann::json heading_json(const heading_result& h);

}  // namespace gyroflip::workflow
