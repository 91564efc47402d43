/// \file
/// \brief Earth rate and its projection on a sensitive axis (see earth.hpp).
#include "gyroflip/earth/earth.hpp"

#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/core/units.hpp"

namespace gyroflip::earth {
namespace {

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto lower = [](char c) {
      return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
    };
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

result<ned_vector> parse_components(std::string_view text) {
  text::token bad;
  const auto c = text::to_doubles(text, ',', &bad);
  if (!c)
    return usage_error(fmt::format("axis '{}': '{}' (column {}) is not a finite number",
                                   printable(text, 60), printable(bad.text, 40), bad.column));
  if (c->size() != 3)
    return usage_error(fmt::format("axis '{}': expected 3 components N,E,D", printable(text, 60)));
  const auto& v = *c;
  const double norm = std::hypot(v[0], v[1], v[2]);
  if (!(norm > 0.0))
    return usage_error(fmt::format("axis '{}': zero vector has no direction", printable(text, 60)));
  return ned_vector{v[0] / norm, v[1] / norm, v[2] / norm};
}

}  // namespace

result<ned_vector> parse_axis(std::string_view text) {
  const std::string_view t = text::trim(text);
  if (iequals(t, "north") || iequals(t, "n")) return ned_vector{1.0, 0.0, 0.0};
  if (iequals(t, "east") || iequals(t, "e")) return ned_vector{0.0, 1.0, 0.0};
  if (iequals(t, "down") || iequals(t, "d")) return ned_vector{0.0, 0.0, 1.0};
  if (iequals(t, "up") || iequals(t, "u")) return ned_vector{0.0, 0.0, -1.0};
  if (t.find(',') == std::string_view::npos)
    return usage_error(
        fmt::format("axis '{}': expected north|east|down|up or N,E,D", printable(text, 60)));
  return parse_components(t);
}

ned_vector earth_rate_ned_dps(double lat_deg) {
  const double lat_rad = lat_deg * units::rad_per_deg;
  // Exact zeros at the poles/equator keep signed-zero noise out of printed results.
  const double c = std::abs(lat_deg) == 90.0 ? 0.0 : std::cos(lat_rad);
  const double s = lat_deg == 0.0 ? 0.0 : std::sin(lat_rad);
  return {earth_rate_wgs84_dps * c, 0.0, -earth_rate_wgs84_dps * s};
}

double earth_rate_component_dps(double lat_deg, const ned_vector& axis) {
  const ned_vector w = earth_rate_ned_dps(lat_deg);
  return w.north * axis.north + w.east * axis.east + w.down * axis.down;
}

status check_latitude(double lat_deg) {
  if (!std::isfinite(lat_deg) || lat_deg < -90.0 || lat_deg > 90.0)
    return usage_error(fmt::format("latitude {} deg is outside [-90, 90]", lat_deg));
  return ok();
}

}  // namespace gyroflip::earth
