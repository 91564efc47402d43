/// \file
/// \brief `gyroflip` executable: a thin shell around the library (see docs/cli.md).
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <exception>
#include <system_error>

#include "cli.hpp"

int main(int argc, char** argv) {
  // A reader that stops early (`gyroflip compensate big.csv | head`) is not an error: ignore
  // SIGPIPE and turn the resulting EPIPE write failure into a quiet exit 0.
  std::signal(SIGPIPE, SIG_IGN);
  try {
    return gyroflip::app::run_cli(argc, argv);
  } catch (const std::system_error& e) {
    if (e.code() == std::errc::broken_pipe) return 0;
    std::fprintf(stderr, "gyroflip: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gyroflip: internal error: %s\n", e.what());
    return 1;
  }
}
