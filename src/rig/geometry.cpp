/// \file
/// \brief Sensor axes on the turntable (formulas in geometry.hpp).
#include "gyroflip/rig/geometry.hpp"

#include <cmath>
#include <numbers>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/units.hpp"

namespace gyroflip::rig {
namespace {

using earth::ned_vector;

double dot(const ned_vector& a, const ned_vector& b) {
  return a.north * b.north + a.east * b.east + a.down * b.down;
}
ned_vector cross(const ned_vector& a, const ned_vector& b) {
  return {a.east * b.down - a.down * b.east, a.down * b.north - a.north * b.down,
          a.north * b.east - a.east * b.north};
}
ned_vector axpy(double k, const ned_vector& x, const ned_vector& y) {
  return {k * x.north + y.north, k * x.east + y.east, k * x.down + y.down};
}
ned_vector scaled(double k, const ned_vector& x) {
  return axpy(k, x, ned_vector{});
}
double norm(const ned_vector& a) {
  return std::sqrt(dot(a, a));
}

// Rodrigues rotation of v about unit a by (cos c, sin s).
ned_vector rotate(const ned_vector& v, const ned_vector& a, double c, double s) {
  return axpy(dot(a, v) * (1.0 - c), a, axpy(s, cross(a, v), scaled(c, v)));
}

}  // namespace

double azimuth_deg_of(const ned_vector& v) {
  if (std::hypot(v.north, v.east) < 1e-12) return std::numeric_limits<double>::quiet_NaN();
  const double a = std::atan2(v.east, v.north) / units::rad_per_deg;
  return a < 0.0 ? a + 360.0 : a;
}

result<rig_geometry> rig_geometry::make(double lat_deg, std::string_view axis_text,
                                        std::string_view table_axis_text, const rig_mount& mount) {
  if (auto s = earth::check_latitude(lat_deg); !s) return s.err();
  rig_geometry g;
  g.lat_deg = lat_deg;
  if (mount.azimuth_set()) {
    if (!(std::abs(mount.azimuth_deg) <= 360.0))
      return parameter_error("azimuth_deg", "the azimuth is in [-360, 360] deg");
    const double az = mount.azimuth_deg * units::rad_per_deg;
    g.sensitive_axis = {std::cos(az), std::sin(az), 0.0};
  } else {
    auto s_axis = earth::parse_axis(axis_text);
    if (!s_axis) return s_axis.err();
    g.sensitive_axis = *s_axis;
  }
  if (table_axis_text.empty()) {
    const ned_vector h = cross(ned_vector{0.0, 0.0, 1.0}, g.sensitive_axis);
    // Vertical sensitive axis: any horizontal axis flips it; take east.
    g.table_axis = norm(h) < 1e-9 ? ned_vector{0.0, 1.0, 0.0} : scaled(1.0 / norm(h), h);
  } else {
    auto a = earth::parse_axis(table_axis_text);
    if (!a) return a.err();
    g.table_axis = *a;
  }
  if (!(std::isfinite(mount.tilt_mrad) && std::abs(mount.tilt_mrad) <= 100.0) ||
      !std::isfinite(mount.tilt_azimuth_deg))
    return parameter_error("tilt_mrad", "the table's tilt is within +-100 mrad");
  if (mount.tilt_mrad != 0.0) {
    // Relative to the rig (its sensitive axis at table 0) when the rig has an azimuth: turning
    // the base turns the tilt with it.
    const double taz = (mount.tilt_azimuth_deg + (mount.azimuth_set() ? mount.azimuth_deg : 0.0)) *
                       units::rad_per_deg;
    const ned_vector h{std::cos(taz), std::sin(taz), 0.0};
    const ned_vector k = cross(g.table_axis, h);
    if (norm(k) < 1e-6)
      return parameter_error("tilt_azimuth_deg",
                             "the table axis cannot lean toward its own direction");
    const ned_vector ku = scaled(1.0 / norm(k), k);
    const double t = mount.tilt_mrad * 1e-3;
    g.table_axis = rotate(g.table_axis, ku, std::cos(t), std::sin(t));
    g.sensitive_axis = rotate(g.sensitive_axis, ku, std::cos(t), std::sin(t));
  }
  const ned_vector y = axpy(-dot(g.table_axis, g.sensitive_axis), g.sensitive_axis, g.table_axis);
  if (norm(y) < 1e-6) {
    return usage_error("table axis is parallel to the sensitive axis: a turn would not flip it");
  }
  g.y0 = scaled(1.0 / norm(y), y);
  g.z0 = cross(g.sensitive_axis, g.y0);
  return g;
}

frame_terms terms_at(const rig_geometry& g, double angle_deg) {
  // Exact values at multiples of 90 deg keep the 0/180 positions free of rounding noise.
  const double r = std::remainder(angle_deg, 360.0);
  double c = 0.0;
  double s = 0.0;
  if (r == 0.0) {
    c = 1.0;
  } else if (r == 180.0 || r == -180.0) {
    c = -1.0;
  } else if (r == 90.0) {
    s = 1.0;
  } else if (r == -90.0) {
    s = -1.0;
  } else {
    c = std::cos(r * units::rad_per_deg);
    s = std::sin(r * units::rad_per_deg);
  }
  const ned_vector ex = rotate(g.sensitive_axis, g.table_axis, c, s);
  const ned_vector ey = rotate(g.y0, g.table_axis, c, s);
  const ned_vector ez = rotate(g.z0, g.table_axis, c, s);
  const auto in_sensor = [&](const ned_vector& w) {
    return sensor::sensor_vec{dot(w, ex), dot(w, ey), dot(w, ez)};
  };
  return {in_sensor(earth::earth_rate_ned_dps(g.lat_deg)), in_sensor(ned_vector{0.0, 0.0, -1.0}),
          in_sensor(g.table_axis), in_sensor(g.sensitive_axis)};
}

}  // namespace gyroflip::rig
