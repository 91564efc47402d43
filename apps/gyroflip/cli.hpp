/// \file
/// \brief Entry point of the command-line interface.
#pragma once

namespace gyroflip::app {

/// Parses `argv`, runs the chosen subcommand and returns the process exit code.
int run_cli(int argc, char** argv);

}  // namespace gyroflip::app
