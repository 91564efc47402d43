/// \file
/// \brief Options and entry points of the `gyroflip` subcommands.
///
/// Each subcommand has an options struct, bound to flags in cli.cpp (the only CLI11
/// translation unit), and a `run_<sub>` in cmd_<sub>.cpp that returns the exit code:
/// 0 ok, 1 runtime failure, 2 bad usage or input (docs/cli.md).
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::app {

/// Prints `gyroflip: error: <message>` on stderr and returns the exit code for `e`.
int report(const error& e);

/// Prints `gyroflip: warning: <message>` on stderr (the run goes on).
void warn(std::string_view message);

/// Prints `gyroflip: note: <message>` on stderr: something the reader noticed and accepted.
void note(std::string_view message);

struct earth_options {
  double lat_deg = 0.0;
  std::string axis = "north";
  bool json = false;
};
int run_earth(const earth_options& o);

struct heading_options {
  std::vector<std::string> runs;
  double lat_deg = 0.0;
  std::string table_axis;               // up|down; empty: the recordings' own, else up
  std::optional<double> base_turn_deg;  // two runs: the base's turn between them
  std::string sensor;                   // for the dead-time bound
  int harmonics = 1;                    // 1 or 2
  bool json = false;
};
int run_heading(const heading_options& o);

struct calibrate_options {
  std::vector<std::string> files;
  double lat_deg = std::numeric_limits<double>::quiet_NaN();  // NaN: not given
  std::string axis;                                           // empty: not given
  std::string pairing = "abba";
  double angle_tolerance_deg = 0.0;  // an encoder angle this close to 0/180 reads as it
  std::size_t degree = 1;
  bool degree_given = false;
  std::string output;  // -o CAL.json
  bool json = false;
  std::string sensor;   // --sensor NAME|FILE.toml: the specification the g-term is checked against
  bool strict = false;  // --strict: refuse a run that is not stationary
  // --explain: the separability report of a table (--positions, --table-axis) before any run,
  // or of the recordings' tables, without calibrating (issue 33 item 2)
  bool explain = false;
  std::string positions;   // --positions A,B,... (with --explain)
  std::string table_axis;  // --table-axis (with --explain; else the recordings' `# table_axis:`)
};
int run_calibrate(const calibrate_options& o);

struct report_options {
  std::vector<std::string> files;
  std::string output;                                         // -o DIR
  double lat_deg = std::numeric_limits<double>::quiet_NaN();  // NaN: not given
  std::string axis;                                           // empty: not given
  std::string calibration;  // CAL.json: compensate the files (else: calibrate them)
  std::string title;
  std::string sensor;  // --sensor NAME|FILE.toml: the specification the g-term is checked against
  std::string pairing = "abba";
  std::optional<double> expected_rate_dps;  // nullopt: not given
  std::vector<std::string> command_line;    // as typed, for the page's provenance
};
int run_report(const report_options& o);

struct reproduce_options {
  bool quick = false;  // one campaign, runs a quarter as long
  std::string output;  // -o DIR: summary.json
  std::uint64_t seed = 1;
  std::optional<std::size_t> campaigns;   // none: 10 (1 with --quick)
  std::vector<std::string> sensors;       // NAME=FILE.toml: a sensor model instead of a preset
  std::vector<std::string> command_line;  // as typed, for the page's provenance
};
int run_reproduce(const reproduce_options& o);

struct compensate_options {
  std::string file;
  double delta_n_dps = std::numeric_limits<double>::quiet_NaN();  // NaN: not given
  std::string calibration;
  std::string pairing;  // empty: from the calibration file, else abba
  double angle_tolerance_deg = 0.0;
  std::string output;  // -o OUT.csv; empty: stdout unless --json
  bool json = false;
  double drift_window_s = 100.0;
  bool strict = false;  // --strict: refuse a calibration made of a run that is not stationary
};
int run_compensate(const compensate_options& o);

}  // namespace gyroflip::app
