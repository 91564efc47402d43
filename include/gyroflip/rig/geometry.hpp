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

#include <optional>
#include <string_view>

#include "gyroflip/core/result.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/sensor/gyro.hpp"

namespace gyroflip::rig {

struct rig_geometry {
  double lat_deg = 0.0;              ///< geodetic latitude (deg)
  earth::ned_vector sensitive_axis;  ///< s at table angle 0 (unit, NED)
  earth::ned_vector table_axis;      ///< turntable axis a (unit, NED)
  earth::ned_vector y0, z0;          ///< the other sensor axes at table angle 0 (unit, NED)

  /// From a latitude and axis texts (earth::parse_axis syntax); `table_axis_text` empty =
  /// default above. Errors: bad latitude or axis, table axis parallel to s.
  [[nodiscard]] static result<rig_geometry> make(double lat_deg, std::string_view axis_text,
                                                 std::string_view table_axis_text);
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

/// The rate the gyro senses from a vector in sensor axes: v_x + c_y v_y + c_z v_z.
[[nodiscard]] inline double sensed(const sensor::sensor_vec& v, const sensor::sensor_params& p) {
  return v.x + p.cross_axis_y * v.y + p.cross_axis_z * v.z;
}

}  // namespace gyroflip::rig
