/// \file
/// \brief `gyroflip adev` and `gyroflip noise`: options and entry points.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "commands.hpp"

namespace gyroflip::app {

/// Input options shared by `adev` and `noise`.
struct series_input {
  std::string file;
  std::string column = "rate_dps";
  double rate_hz = std::numeric_limits<double>::quiet_NaN();  // NaN: from time_s
  std::string input = "rate";                                 // rate | angle
  std::string dataset;                                        // HDF5 dataset path
};

/// A series ready for analysis: its phase (angle, deg) and sample interval.
struct analysis_input {
  std::vector<double> phase;
  double tau0_s = 0.0;
  std::size_t samples = 0;
};
/// Reads `in.file` (CSV column, .npy or raw float64) and builds the phase for `in.input`.
result<analysis_input> load_series(const series_input& in);

struct adev_options {
  series_input in;
  std::string kind = "oadev";
  std::string taus = "octave";
  double ci = 0.683;
  bool json = false;
  std::string output;
};
int run_adev(const adev_options& o);

}  // namespace gyroflip::app

namespace gyroflip::app {

struct noise_options {
  series_input in;
  double ci = 0.683;  ///< two-sided confidence level of the terms' intervals
  bool json = false;
};
int run_noise(const noise_options& o);

}  // namespace gyroflip::app
