/// \file
/// \brief WGS84 Earth rotation rate and its component along a gyro's sensitive axis.
///
/// Frame: local North-East-Down (NED). The Earth-rate vector there is
/// W_E (cos(lat), 0, -sin(lat)) (FACTS §2). A sensitive axis is given at the
/// table's 0 deg position as a NED vector or by name. Used by `gyroflip earth`,
/// `gyroflip calibrate` (split of dN into Earth and g terms) and the simulator.
#pragma once

#include <string_view>

#include "gyroflip/core/result.hpp"
#include "gyroflip/core/units.hpp"

namespace gyroflip::earth {

/// WGS84 angular velocity of the Earth (rad/s), GeographicLib `Constants::WGS84_omega()`.
inline constexpr double earth_rate_wgs84_rad_s = 7.2921150e-5;

/// WGS84 angular velocity of the Earth (deg/s) = 4.178074e-3 (paper section 2).
inline constexpr double earth_rate_wgs84_dps = earth_rate_wgs84_rad_s / units::rad_per_deg;

/// A direction in the local NED frame (components dimensionless).
struct ned_vector {
  double north = 0.0;
  double east = 0.0;
  double down = 0.0;
};

/// Parses `north|east|down|up` (case-insensitive, also `n|e|d|u`) or `N,E,D` components.
/// The result is normalised to unit length. Errors: empty, unknown name, non-numeric or
/// non-finite component, wrong component count, zero vector.
[[nodiscard]] result<ned_vector> parse_axis(std::string_view text);

/// The Earth-rate vector in NED (deg/s) at geodetic latitude `lat_deg` (degrees, [-90, 90]):
/// W_E (cos lat, 0, -sin lat). FACTS §2.
[[nodiscard]] ned_vector earth_rate_ned_dps(double lat_deg);

/// Earth-rate component along the unit sensitive axis `axis` (deg/s): W_E (u_E . s).
/// For `axis` = north this is paper eqn 9, W_E cos(lat) (3.0755e-3 deg/s at 42.6 deg N);
/// for `up` it is W_E sin(lat). `axis` must be a unit vector (from parse_axis).
[[nodiscard]] double earth_rate_component_dps(double lat_deg, const ned_vector& axis);

/// Checks a latitude (degrees): finite and within [-90, 90].
[[nodiscard]] status check_latitude(double lat_deg);

}  // namespace gyroflip::earth
