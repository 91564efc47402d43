/// \file
/// \brief The helper programs a report runs (gnuplot for figures, Chromium or pdfunite for
/// report.pdf) and how a program stops them when it is stopped itself.
///
/// Each helper runs in its own process group, and is killed by the kernel if the caller dies
/// first (Linux's parent-death signal). A program that catches SIGINT, SIGTERM or SIGHUP calls
/// stop_helper_programs() from its handler, so that no gnuplot or Chromium (nor a process
/// Chromium started) outlives it writing into a folder that is being removed; the CLI does,
/// apps/gyroflip/main.cpp.
#pragma once

namespace gyroflip::report {

/// Kills (SIGKILL) the process group of every helper running now and waits for each helper.
/// Async-signal-safe (kill(2), waitpid(2) only): for signal handlers, before the temporaries are
/// removed (io::remove_temporary_files).
void stop_helper_programs() noexcept;

}  // namespace gyroflip::report
