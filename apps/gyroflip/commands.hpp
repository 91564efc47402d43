/// \file
/// \brief Options and entry points of the `gyroflip` subcommands.
///
/// Each subcommand has an options struct, bound to flags in cli.cpp (the only CLI11
/// translation unit), and a `run_<sub>` in cmd_<sub>.cpp that returns the exit code:
/// 0 ok, 1 runtime failure, 2 bad usage or input (docs/cli.md).
#pragma once

#include <optional>
#include <string>

#include "gyroflip/core/result.hpp"

namespace gyroflip::app {

/// Prints `gyroflip: error: <message>` on stderr and returns the exit code for `e`.
int report(const error& e);

struct earth_options {
  double lat_deg = 0.0;
  std::string axis = "north";
  bool json = false;
};
int run_earth(const earth_options& o);

}  // namespace gyroflip::app
