/// \file
/// \brief Runs the `gyroflip` executable from a test and captures its exit code and output.
#pragma once

#include <string>
#include <vector>

namespace gyroflip::test {

struct cli_result {
  int exit_code = -1;
  std::string out;
  std::string err;
  long max_rss_kb = 0;  ///< peak resident memory of the run (getrusage, KiB)
};

/// Runs GYROFLIP_EXE with `args` (no shell), stdin from /dev/null.
cli_result run_cli(const std::vector<std::string>& args);

/// Runs another program: argv[0] looked up on PATH, the rest its arguments (no shell).
cli_result run_program(const std::vector<std::string>& argv);

/// Starts GYROFLIP_EXE with `args` in the background (stdin, stdout and stderr to /dev/null) and
/// returns its process id; `wait_cli` returns its exit status (128 + N when killed by signal N).
int spawn_cli(const std::vector<std::string>& args);
int wait_cli(int pid);

/// Reads a whole file (empty string if missing).
std::string read_text(const std::string& path);

/// A report page's HTML without the no-break spans its text is set in (report/page.cpp, issue
/// 31): the text as written, for finding a phrase in it.
std::string read_page(const std::string& path);

/// Writes a whole file.
void write_text(const std::string& path, const std::string& text);

/// True when a file or directory exists.
bool exists(const std::string& path);

}  // namespace gyroflip::test
