/// \file
/// \brief `gyroflip simulate` and `gyroflip sensors`: options and entry points.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

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
  int n_avg = 256;
  std::uint64_t seed = 1;
  bool raw = false;
  std::string out = "-";
  std::string truth;
  double settle_s = 0.08;
  std::string positions = "0,180";
  bool no_flip = false;  ///< stay at the first position (a stationary, unflipped recording)
  double power_on_before_s = 0.0;
  int filter_word = 94;
  bool no_chop = false;
  int steps_per_rev = 200;
  double step_rate_sps = 400.0;
  double start_rate_sps = 200.0;
  double accel_sps2 = 2000.0;
};
int run_simulate(const simulate_options& o);

struct sensors_options {
  bool json = false;
};
int run_sensors(const sensors_options& o);

}  // namespace gyroflip::app
