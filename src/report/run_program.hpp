/// \file
/// \brief Private to the report module: runs a program (gnuplot, chromium, pdfunite) in a
/// folder, waits for it, and keeps the start of what it wrote to stderr for the message.
#pragma once

#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::report::detail {

struct program_run {
  int exit_code = -1;    ///< 127: not found; -1: killed by a signal
  std::string messages;  ///< stderr, at most ~2000 bytes
};

/// Runs argv[0] (searched on PATH) with `argv` in folder `dir`, stdout to /dev/null. Errors:
/// the program could not be started.
[[nodiscard]] result<program_run> run_program(const std::vector<std::string>& argv,
                                              const std::string& dir);

}  // namespace gyroflip::report::detail
