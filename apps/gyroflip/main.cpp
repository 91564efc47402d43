/// \file
/// \brief `gyroflip` executable: a thin shell around the library (see docs/cli.md).
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <exception>
#include <system_error>

#include "cli.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/report/helpers.hpp"

namespace {

// SIGINT, SIGTERM, SIGHUP: stop the helper programs (gnuplot, Chromium: they write into the
// temporaries), remove the outputs' temporary files and folders, then die of the same signal
// (the shell sees 128 + N, as for any killed program). Only async-signal-safe calls here.
extern "C" void on_fatal_signal(int sig) {
  gyroflip::report::stop_helper_programs();
  gyroflip::io::remove_temporary_files();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_fatal_signal;
  sigemptyset(&sa.sa_mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  install_signal_handlers();
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
