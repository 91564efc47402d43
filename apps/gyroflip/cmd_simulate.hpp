/// \file
/// \brief `gyroflip simulate` and `gyroflip sensors`: options and entry points.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "rig_options.hpp"

namespace gyroflip::app {

struct simulate_options {
  std::string sensor;  ///< preset name or TOML file
  double duration_s = 3600.0;
  std::optional<double> temp_c;  ///< constant temperature
  std::string temp_profile;      ///< spec or CSV file (rig/profiles.hpp)
  double lat_deg = 42.6;
  std::string axis = "north";
  std::string table_axis;  ///< empty = perpendicular horizontal default
  std::string rate_profile = "0";
  std::uint64_t seed = 1;
  bool raw = false;
  std::string out = "-";
  std::string truth;
  rig_options rig;       ///< the rig's settings (rig_options.hpp)
  bool no_flip = false;  ///< stay at the first position (a stationary, unflipped recording)
  double power_on_before_s = 0.0;
  std::string order = "auto";         ///< auto|sweep|cycle (rig::visit_order)
  std::optional<double> azimuth_deg;  ///< the sensitive axis at table 0, horizontal (north finding)
  double tilt_mrad = 0.0;             ///< the rig's tilt
  double tilt_azimuth_deg = 0.0;      ///< where the table axis leans (from the axis's azimuth)
};
int run_simulate(const simulate_options& o);

struct sensors_options {
  bool json = false;
  double dead_s = 0.4;    ///< --dead-time: turn + settle per turn for the implied dwell (s)
  double lat_deg = 42.6;  ///< --latitude: for the implied heading limit (deg)
};
int run_sensors(const sensors_options& o);

}  // namespace gyroflip::app
