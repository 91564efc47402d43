/// \file
/// \brief Rig geometry: where the sensor's axes point at any table angle, and what the sensor
/// then sees of the Earth rate, gravity, the table rate and a rate-table input.
///
/// Frames: local NED (earth module). Sensor axes at table angle 0: x0 = s (sensitive axis),
/// y0 = the table axis a made perpendicular to s (y0 = a when a is perpendicular to s),
/// z0 = x0 x y0. At table angle theta every sensor axis is turned about a by theta (Rodrigues):
/// e_i(theta) = e_i0 cos + (a x e_i0) sin + a (a . e_i0)(1 - cos). A world vector w has the
/// sensor components w . e_i(theta).
///
/// Specific force of a rig at rest: f = -g_vector = 1 g pointing up = (0, 0, -1) g in NED
/// (what an accelerometer reads; the g-sensitivity acts on it). Default table axis: the
/// horizontal direction down x s (east for a north sensitive axis), or east when s is vertical,
/// so that a 180-deg turn reverses both s and the sensor's "up" (paper Fig. 1).
#pragma once

#include <cmath>
#include <limits>
#include <optional>
#include <string_view>

#include "gyroflip/core/result.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/sensor/gyro.hpp"

namespace gyroflip::rig {

/// Where the rig stands, beyond the axis texts (issue 33, north finding).
struct rig_mount {
  /// When finite: the sensitive axis at table angle 0 is horizontal at this azimuth (deg from
  /// north, clockwise), instead of the axis text.
  double azimuth_deg = std::numeric_limits<double>::quiet_NaN();
  /// The whole rig (table axis and sensor) tilted by this angle (mrad) so that the table axis
  /// leans toward the horizontal direction at `tilt_azimuth_deg` (from north, clockwise; from
  /// the sensitive axis's azimuth when `azimuth_deg` is set, so that the tilt turns with the
  /// rig's base): a rotation about (a x h) / |a x h| (h that direction) by tilt_mrad / 1000
  /// rad, applied to s and a.
  double tilt_mrad = 0.0;
  double tilt_azimuth_deg = 0.0;
  [[nodiscard]] bool azimuth_set() const noexcept { return std::isfinite(azimuth_deg); }
};

struct rig_geometry {
  double lat_deg = 0.0;              ///< geodetic latitude (deg)
  earth::ned_vector sensitive_axis;  ///< s at table angle 0 (unit, NED)
  earth::ned_vector table_axis;      ///< turntable axis a (unit, NED)
  earth::ned_vector y0, z0;          ///< the other sensor axes at table angle 0 (unit, NED)

  /// From a latitude and axis texts (earth::parse_axis syntax); `table_axis_text` empty =
  /// default above. Errors: bad latitude or axis, table axis parallel to s.
  [[nodiscard]] static result<rig_geometry> make(double lat_deg, std::string_view axis_text,
                                                 std::string_view table_axis_text,
                                                 const rig_mount& mount = {});
};

/// What the sensor sees at one table angle, in sensor axes.
struct frame_terms {
  sensor::sensor_vec earth_dps;         ///< Earth-rate vector (deg/s)
  sensor::sensor_vec specific_force_g;  ///< specific force (g)
  sensor::sensor_vec table_axis;        ///< unit table axis (constant: a is fixed by the turn)
  sensor::sensor_vec input_axis;        ///< unit direction of a rate-table input (s at 0 deg)
};

/// The terms at table angle `angle_deg` (deg, any value).
[[nodiscard]] frame_terms terms_at(const rig_geometry& g, double angle_deg);

/// The azimuth (deg from north, clockwise, [0, 360)) of a vector's horizontal part; NaN when it
/// has none.
[[nodiscard]] double azimuth_deg_of(const earth::ned_vector& v);

/// The rate the gyro senses from a vector in sensor axes: v_x + c_y v_y + c_z v_z.
[[nodiscard]] inline double sensed(const sensor::sensor_vec& v, const sensor::sensor_params& p) {
  return v.x + p.cross_axis_y * v.y + p.cross_axis_z * v.z;
}

}  // namespace gyroflip::rig
