/// \file
/// \brief Unit factors of gyro specifications, named, with their definitions, so that no code
/// multiplies by a bare 3600 or 60. IEEE Std 952-1997 Annex C units (FACTS §7): a rate in °/s or
/// °/h, angle random walk N in °/√s (= °/s/√Hz, ADEV at 1 s) or °/√h, bias instability B in °/s or
/// °/h, rate random walk K in °/s/√s or °/h/√h, rate ramp R in °/s² or °/h².
#pragma once

#include <numbers>
#include <string_view>

namespace gyroflip::units {

inline constexpr double s_per_h = 3600.0;
/// A rate or B: x [°/h] = x [°/s] * 3600.
inline constexpr double dph_per_dps = s_per_h;
/// N: x [°/√h] = x [°/√s] * √3600 = 60 x.
inline constexpr double deg_rth_per_deg_rts = 60.0;
/// K: x [°/h/√h] = x [°/s/√s] * 3600 * 60.
inline constexpr double dph_rth_per_dps_rts = s_per_h * deg_rth_per_deg_rts;
/// R: x [°/h²] = x [°/s²] * 3600².
inline constexpr double dph2_per_dps2 = s_per_h * s_per_h;
/// Angles: x [rad] = x [°] * π/180.
inline constexpr double rad_per_deg = std::numbers::pi / 180.0;

/// Degrees per unit of a series' samples: `rad/s` and `rad` 180/π, `deg/h` 1/3600, else (`deg/s`,
/// `deg`) 1. The names are those of `gyroflip adev --units` and `gyroflip.noise(units=...)`.
[[nodiscard]] constexpr double deg_per_unit(std::string_view unit) noexcept {
  if (unit == "rad/s" || unit == "rad") return 1.0 / rad_per_deg;
  if (unit == "deg/h") return 1.0 / s_per_h;
  return 1.0;
}

/// The name of the samples' unit for an `angle` (or rate) series given `unit`: the defaults read
/// as the input's kind (deg/s for a rate, deg for an angle).
[[nodiscard]] constexpr std::string_view unit_name(bool angle, std::string_view unit) noexcept {
  if (angle) return unit == "rad" || unit == "rad/s" ? "rad" : "deg";
  return unit == "deg" ? "deg/s" : unit == "rad" ? "rad/s" : unit;
}

/// Standard gravity g_n = 9.80665 m/s² (3rd CGPM 1901; ISO 80000-3; FACTS §7.2): what datasheets
/// mean by g, mg and µg.
inline constexpr double standard_gravity_mps2 = 9.80665;

/// Accelerometer units of a series' samples (IEEE Std 1293-2018 terms, FACTS §7.2): `m/s^2`,
/// `g`, `mg`, `ug`.
[[nodiscard]] constexpr bool is_accel_unit(std::string_view unit) noexcept {
  return unit == "m/s^2" || unit == "g" || unit == "mg" || unit == "ug";
}

/// m/s² per unit of an accelerometer series' samples (`g`: g_n; `mg`, `ug`: 1e-3, 1e-6 g_n); 1
/// for `m/s^2`.
[[nodiscard]] constexpr double mps2_per_unit(std::string_view unit) noexcept {
  if (unit == "g") return standard_gravity_mps2;
  if (unit == "mg") return standard_gravity_mps2 * 1e-3;
  if (unit == "ug") return standard_gravity_mps2 * 1e-6;
  return 1.0;
}

static_assert(deg_rth_per_deg_rts * deg_rth_per_deg_rts == s_per_h, "sqrt(3600) = 60");

}  // namespace gyroflip::units
