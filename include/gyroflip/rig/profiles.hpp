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
///   a table (temperature)            `table()`: linear interpolation, held constant outside it
///                                    (the CLI reads `FILE.csv` with columns time_s,temp_c through
///                                    io::read_time_table, the one CSV reader)
/// Evaluation is O(1) amortised for non-decreasing times (a cursor). Every kind but `sine` is
/// piecewise affine, and is evaluated as v0 + slope (t - t0) on its current piece, one formula
/// for `at` and for the simulator's block evaluation `fill` (so both give the same bits).
#pragma once

#include <cstddef>
#include <cstdint>
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
  /// A temperature spec (degC): const, steps, ramp or fridge. Errors name the spec.
  [[nodiscard]] static result<profile> parse_temperature(std::string_view spec);
  /// True when `spec` has the form of a temperature spec (else it names a table file, which the
  /// caller reads: io::read_time_table).
  [[nodiscard]] static bool is_temperature_spec(std::string_view spec);
  /// Linear interpolation between (t_s[i], v[i]) (held before the first and after the last).
  /// Errors: sizes differ or are 0, a value not finite, times not increasing (row named).
  [[nodiscard]] static result<profile> table(std::vector<double> t_s, std::vector<double> v);

  /// The value at `t_s` (s).
  double at(double t_s) noexcept {
    if (kind_ == kind::constant) return value_;
    return eval(t_s);
  }
  /// The values at the non-decreasing times `t_s[0..n)` (s) into `out`: the same numbers as n
  /// calls of at() in order, but one piece at a time (a tight loop per piece, no per-sample
  /// dispatch; the simulator's temperature and rate columns).
  void fill(const double* t_s, double* out, std::size_t n) noexcept;
  [[nodiscard]] bool is_constant() const noexcept { return kind_ == kind::constant; }
  /// Error unless every value the profile takes lies in [lo, hi] (`what` names it, e.g. "the
  /// temperature (degC)"): the simulator's physics is only defined there.
  [[nodiscard]] status check_range(std::string_view what, double lo, double hi) const;
  /// Shortest time a profile may resolve (s): ramps, fridge periods; 1/highest sine frequency.
  static constexpr double min_time_s = 1e-3;

 private:
  // A piece on which the profile is affine: v0 + slope (t - t0) for times before t_end_s.
  struct piece {
    double t0_s, v0, slope_per_s, t_end_s;
    // Slope 0 returns v0 itself (no rounding, and a constant -0 stays -0).
    [[nodiscard]] double at(double t_s) const noexcept {
      return slope_per_s == 0.0 ? v0 : v0 + slope_per_s * (t_s - t0_s);
    }
  };
  double eval(double t_s) noexcept;
  // The piece that holds `t_s` (moves the cursor); not for `sine`.
  piece piece_at(double t_s) noexcept;
  piece triangle_piece(std::int64_t half) const noexcept;
  // The syntax both kinds share: a number, const:V, steps:T:V,... (nullopt: none of these).
  static std::optional<result<profile>> parse_shared(std::string_view what, std::string_view spec,
                                                     std::optional<double> before_steps);
  kind kind_ = kind::constant;
  double value_ = 0.0;  // constant; sine/triangle offset (mean)
  double amp_ = 0.0, freq_hz_ = 0.0;
  double half_period_s_ = 0.0;  // triangle: one falling or rising half (s)
  std::vector<double> t_s_, v_;
  std::size_t cursor_ = 0;  // hold/linear: current knot
  std::int64_t half_ = -1;  // triangle: current half-period index (-1: none yet)
};

}  // namespace gyroflip::rig
