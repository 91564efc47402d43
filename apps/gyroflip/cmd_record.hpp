/// \file
/// \brief `gyroflip record` and `gyroflip export`: the rig's recorder and its files.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rig_options.hpp"

namespace gyroflip::app {

struct record_options {
  std::string port;
  unsigned baud = 115200;
  std::string output;  ///< RUN.gfr
  double duration_s = 0.0;
  std::string sensor = "hz1-90-100a";  ///< its nominal scale factor converts codes to deg/s
  // CONFIGURE (docs/PROTOCOL.md); defaults are the paper's rig.
  rig_options rig;
  /// How the device visits the positions: auto, cycle or there-and-back (rig::device_order).
  std::string order = "auto";
  bool raw = false;  ///< keep every gyro conversion (RAW frames)
  /// Where the rig stands (stored in META, issue 33): the table's axis (as simulate's
  /// --table-axis) and the azimuth of the sensitive axis at the table's 0 deg (deg from north,
  /// clockwise). Empty / unset: not recorded.
  std::string table_axis;
  std::optional<double> azimuth_deg;
  double reconnect_timeout_s = 60.0;
  double temp_mv_per_c = 8.4;   ///< the temperature channel's output per degC
  double temp_at_0v_c = 24.85;  ///< the temperature at 0 V on that channel
  bool json_progress = false;
  std::vector<std::string> command_line;
};
int run_record(const record_options& o);

struct export_options {
  std::string file;
  std::string output;
  bool raw = false;
  bool strict = false;  ///< a damaged region is an error, not skipped with a warning
};
int run_export(const export_options& o);

}  // namespace gyroflip::app
