/// \file
/// \brief Time profiles of the rig: the input rate of a rate table and the temperature.
///
/// Spec syntax (CLI `--rate-profile`, `--temp-profile`; times in s from the run start):
///   `V` or `const:V`                 constant V
///   `steps:T0:V0,T1:V1,...`          V_i from T_i on (T increasing); before T0 the value is 0
///                                    for a rate, V0 for a temperature
///   `sine:AMP:FREQ_HZ[:OFFSET]`      OFFSET + AMP sin(2 pi FREQ t)           (rate only)
///   `ramp:FROM:TO:DURATION_S`        linear FROM -> TO over DURATION, then TO (temperature)
///   `fridge:MEAN:SWING:PERIOD_S`     triangle wave MEAN +- SWING/2 (compressor cycling), starting
///                                    at MEAN + SWING/2                       (temperature)
///   FILE (temperature)               CSV with header `time_s,temp_c`, linear interpolation,
///                                    held constant outside the table
/// Evaluation is O(1) amortised for non-decreasing times (a cursor).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::rig {

class profile {
 public:
  enum class kind { constant, hold, linear, sine, triangle };

  /// The constant `value`.
  [[nodiscard]] static profile constant(double value);
  /// A rate spec (deg/s): const, steps or sine. Errors name the spec.
  [[nodiscard]] static result<profile> parse_rate(std::string_view spec);
  /// A temperature spec (degC): const, steps, ramp, fridge, or a CSV file (errors FILE:LINE:COL).
  [[nodiscard]] static result<profile> parse_temperature(std::string_view spec_or_file);
  /// The CSV temperature table in `text`; `file` names it in messages.
  [[nodiscard]] static result<profile> parse_temperature_csv(std::string_view text,
                                                             std::string_view file);

  /// The value at `t_s` (s).
  double at(double t_s) noexcept {
    if (kind_ == kind::constant) return value_;
    return eval(t_s);
  }
  [[nodiscard]] bool is_constant() const noexcept { return kind_ == kind::constant; }

 private:
  double eval(double t_s) noexcept;
  // The syntax both kinds share: a number, const:V, steps:T:V,... (nullopt: none of these).
  static std::optional<result<profile>> parse_shared(std::string_view what, std::string_view spec,
                                                     std::optional<double> before_steps);
  kind kind_ = kind::constant;
  double value_ = 0.0;  // constant; sine/triangle offset (mean)
  double amp_ = 0.0, freq_hz_ = 0.0;
  std::vector<double> t_s_, v_;
  std::size_t cursor_ = 0;
};

}  // namespace gyroflip::rig
