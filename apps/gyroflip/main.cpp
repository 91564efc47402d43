/// \file
/// \brief `gyroflip` executable: a thin shell around the library (see docs/cli.md).
#include <csignal>
#include <cstdio>
#include <exception>

#include "cli.hpp"

int main(int argc, char** argv) {
  try {
    return gyroflip::app::run_cli(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gyroflip: internal error: %s\n", e.what());
    return 1;
  }
}
