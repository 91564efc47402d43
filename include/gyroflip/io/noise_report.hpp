/// \file
/// \brief One series' noise terms as the JSON object `gyroflip noise --json` prints and
/// `gyroflip.noise()` returns (keys in docs/ANALYSIS.md, "noise --json"): each term in the
/// field's units with its interval, or null with its upper limit when the data do not resolve
/// it; the OADEV points, the misfit points and the slope read-offs. Includes only nlohmann's
/// forward header.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/core/result.hpp"

namespace gyroflip::io {

/// What was analysed and what came out.
struct noise_report {
  std::string file;             ///< the input's name
  std::string column;           ///< its column
  std::string input = "rate";   ///< "rate" or "angle"
  std::string units = "deg/s";  ///< the samples' unit
  double deg_per_unit = 1.0;    ///< degrees per unit of the samples (rad/s: 180/pi)
  /// "gyro", or "accel": an accelerometer's specific force in `units` (m/s^2, g, mg, ug), whose
  /// terms are VRW, bias instability and acceleration random walk (IEEE Std 1293-2018).
  std::string quantity = "gyro";
  double mps2_per_unit = 1.0;  ///< m/s^2 per unit of an accelerometer's samples (g: 9.80665)
  double tau0_s = 0.0;
  std::size_t samples = 0;
  analysis::noise_series series;
  analysis::noise_analysis result;
};

/// The JSON object of `r`, schema gyroflip.noise/1 (io/schema.hpp; numbers unchecked: pass it
/// through finite_dump).
[[nodiscard]] nlohmann::json noise_json(const noise_report& r);

/// A column's sensor and unit as its name states them (docs/ANALYSIS.md, "Accelerometers"): the
/// text in a trailing `[...]` or `(...)`, else the name's last one, two or three `_`-separated
/// words (longest first), read case-insensitively with spaces dropped, `^` dropped, `²` as 2, `µ`
/// as u, `°` as deg and `_` as `/`. Accelerometer: m/s2, m/s/s, mps2, g, mg, ug; gyro: deg/s, dps,
/// deg/sec, rad/s, radps, rad/sec, deg/h, dph, deg/hr. `quantity` is "gyro" or "accel", `unit`
/// the canonical name (deg/s, rad/s, deg/h; m/s^2, g, mg, ug); nullopt when the name states none.
struct column_unit {
  std::string quantity;
  std::string unit;
};
[[nodiscard]] std::optional<column_unit> unit_of_column(std::string_view name);

/// One axis for Kalibr's IMU file: its white-noise density and bias random walk in Kalibr's
/// units (gyro rad/s/sqrt(Hz), rad/s^2/sqrt(Hz); accelerometer m/s^2/sqrt(Hz), m/s^3/sqrt(Hz)).
struct kalibr_axis {
  std::string column;
  analysis::noise_term density;      ///< N (ARW or VRW)
  analysis::noise_term random_walk;  ///< K (RRW or acceleration random walk)
};
/// The axis of report `r` in Kalibr's units (N and K converted from the samples' unit).
[[nodiscard]] kalibr_axis kalibr_axis_of(const noise_report& r);

/// What Kalibr's IMU file is made of: both sensors' axes, the topic and the rate.
struct kalibr_imu {
  std::string rostopic = "/imu0";
  double update_rate_hz = 0.0;
  std::string gyro_source, accel_source;  ///< where each sensor's record came from (comments)
  std::vector<kalibr_axis> gyro, accel;
};
/// Kalibr's IMU noise YAML (ethz-asl/kalibr, kalibr_common/ConfigReader.py ImuParameters; the
/// wiki's "IMU Noise Model"): rostopic (a quoted string), update_rate, and the four densities,
/// each the largest of the axes (of its value, or of its upper limit when unresolved), the axes'
/// values as comments. Errors: no gyro or no accelerometer axis, a rate or chosen value that is
/// not finite and positive.
[[nodiscard]] result<std::string> kalibr_yaml(const kalibr_imu& imu);

}  // namespace gyroflip::io
