/// \file
/// \brief The rig's settings as options (simulate, record; emulate takes the board's part):
/// one set of flags (cli.cpp, add_rig_options), one conversion to rig::rig_config, whose check
/// is the one validation.
#pragma once

#include <string>

#include "gyroflip/core/result.hpp"
#include "gyroflip/rig/rig_config.hpp"

namespace gyroflip::app {

struct rig_options {
  int n_avg = 256;
  int n_temp = 4;
  double settle_s = 0.08;
  std::string positions = "0,180";
  int filter_word = 94;
  bool no_chop = false;
  int steps_per_rev = 200;
  int step_rate_sps = 400;
  int start_rate_sps = 200;
  int accel_sps2 = 2000;
  bool one_way = false;
  bool home = false;
  bool hold_coils = false;
};

/// The rig configuration the options give, checked (rig_config::check: errors name the library
/// parameter, which the front end maps to its option).
[[nodiscard]] result<rig::rig_config> rig_config_of(const rig_options& o);

}  // namespace gyroflip::app
