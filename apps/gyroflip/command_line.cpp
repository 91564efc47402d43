/// \file
/// \brief Options several subcommands read alike (command_line.hpp).
#include "command_line.hpp"

#include <string_view>

#include "gyroflip/core/error.hpp"
#include "gyroflip/earth/earth.hpp"

namespace gyroflip::app {

result<std::optional<io::calibration_geometry>> geometry_option(double lat_deg,
                                                                const std::string& axis) {
  const bool has_lat = !std::isnan(lat_deg);
  if (has_lat != !axis.empty())
    return usage_error(
        "--latitude and --axis go together: give both to split dN into Earth and g terms");
  if (!has_lat) return std::optional<io::calibration_geometry>{};
  if (auto s = earth::check_latitude(lat_deg); !s) return s.err();
  auto a = earth::parse_axis(axis);
  if (!a) return a.err();
  return std::optional<io::calibration_geometry>{io::calibration_geometry{lat_deg, *a}};
}

std::string shell_command(const std::vector<std::string>& words) {
  // Characters a POSIX shell takes as they are; anything else is quoted.
  constexpr std::string_view plain =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_./=:,+@%";
  std::string out;
  for (const auto& w : words) {
    if (!out.empty()) out += ' ';
    if (!w.empty() && w.find_first_not_of(plain) == std::string::npos) {
      out += w;
      continue;
    }
    out += '\'';
    for (const char c : w) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    out += '\'';
  }
  return out;
}

}  // namespace gyroflip::app
