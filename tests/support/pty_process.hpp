/// \file
/// \brief A program that serves a pseudo-terminal (`gyroflip emulate --pty`, QEMU's `-serial
/// pty`), run in the background for a test: started through the shell, its pty path read from
/// what it prints, SIGTERMed and waited for when the test ends.
#pragma once

#include <string>

namespace gyroflip::test {

class pty_process {
 public:
  /// Runs `command` in the background, its stdout and stderr to files in `dir`, and waits up to
  /// 5 s for it to print a `/dev/...` path (or ` on /PATH`) ended by a blank or a newline.
  pty_process(const std::string& command, const std::string& dir);
  ~pty_process();
  pty_process(const pty_process&) = delete;
  pty_process& operator=(const pty_process&) = delete;

  /// The pty path, empty when none was printed (then `output()` says why).
  [[nodiscard]] const std::string& pty() const noexcept { return pty_; }
  /// Everything it printed so far (stdout, then stderr).
  [[nodiscard]] std::string output() const;
  /// Its process id (for SIGSTOP and SIGCONT), or -1 when it did not start.
  [[nodiscard]] int pid() const noexcept { return pid_; }

 private:
  std::string out_, err_, pty_;
  int pid_ = -1;
};

}  // namespace gyroflip::test
