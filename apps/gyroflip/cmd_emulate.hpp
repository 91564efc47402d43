/// \file
/// \brief `gyroflip emulate`: the rig's firmware against the simulator, on a serial line.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gyroflip::app {

struct emulate_options {
  std::string sensor = "hz1-90-100a";  ///< preset name or TOML file
  std::optional<double> temp_c;
  std::string temp_profile;
  std::string rate_profile = "0";
  double lat_deg = 42.6;
  std::string axis = "north";
  std::string table_axis;
  std::optional<double> azimuth_deg;  ///< the sensitive axis at table 0, horizontal (north finding)
  double tilt_mrad = 0.0;             ///< the rig's tilt
  double tilt_azimuth_deg = 0.0;      ///< where the table axis leans (from the axis's azimuth)
  std::string truth;                  ///< TRUTH.json: the terms an indexed run should find
  std::string speed = "1";            ///< X (times real time) or max
  bool pty = false;
  std::string port;
  std::uint64_t seed = 1;
  double fault_ber = 0.0;
  double fault_drop = 0.0;
  std::string log;   ///< SENT.csv: every DWELL the device sent
  std::string link;  ///< a symbolic link kept pointing at the line while it is there
  std::vector<double> fault_reset_at_s;    ///< device times of firmware resets
  std::vector<std::string> fault_unplug;   ///< AT_S:FOR_S, the line gone for FOR_S device s
  std::vector<std::string> fault_stall;    ///< AT_S:FOR_S, the emulator stopped FOR_S wall s
  std::vector<std::string> fault_tx_hold;  ///< AT_S:FOR_S, the UART transmitter held FOR_S device s
  /// CMD:N: the device's reply (ACK or NAK) to the Nth frame of command CMD it takes is lost
  std::vector<std::string> fault_lose_reply;
  /// CMD:N: the firmware is reset just before it takes the Nth frame of command CMD
  std::vector<std::string> fault_reset_before;
  bool fault_lose_boot_info = false;  ///< the INFO each boot sends is lost
  /// The board's serial number (INFO); none: a random non-zero one. 0 is a board whose
  /// information flash holds no serial record (docs/RECORDER.md, "A board without a serial").
  std::optional<std::uint32_t> serial;
  double duration_s = 0.0;  ///< simulated seconds to run (0: until SIGINT/SIGTERM)
  double power_on_before_s = 0.0;
  int filter_word = 94;
  bool no_chop = false;
  int steps_per_rev = 200;
  std::string coil_heat;  ///< the coils' heat, RISE_C[:TAU_S] (empty: none)
};
int run_emulate(const emulate_options& o);

}  // namespace gyroflip::app
