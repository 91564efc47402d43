/// \file
/// \brief `gyroflip plan`: options and entry point.
#pragma once

#include <limits>
#include <string>

#include "cmd_adev.hpp"

namespace gyroflip::app {

struct plan_options {
  std::string sensor;  ///< --sensor NAME|FILE.toml (or a static record)
  series_input in;     ///< --static FILE with its column and rate
  double dead_s = std::numeric_limits<double>::quiet_NaN();  ///< --dead-time (required)
  double duration_s = 3600.0;
  double min_dwell_s = 0.01;
  double max_dwell_s = 0.0;  ///< 0: a quarter of the run
  bool json = false;
  std::string positions;       ///< --positions A,B,... (empty: the 0/180 flip)
  std::string order = "auto";  ///< --order: the visiting order planned for (plan_request)
  bool heading = false;        ///< --heading: plan for north finding
  double lat_deg = std::numeric_limits<double>::quiet_NaN();  ///< --latitude (with --heading)
  std::string plot;  ///< --plot FILE.png|.svg|.pdf: the error against the dwell
};
int run_plan(const plan_options& o);

}  // namespace gyroflip::app
