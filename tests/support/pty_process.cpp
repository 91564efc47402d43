/// \file
/// \brief Background programs that serve a pty (pty_process.hpp).
#include "support/pty_process.hpp"

#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "support/run_cli.hpp"

namespace gyroflip::test {

pty_process::pty_process(const std::string& command, const std::string& dir)
    : out_(dir + "/pty_process.out"), err_(dir + "/pty_process.err") {
  const std::string pid_file = dir + "/pty_process.pid";
  const std::string cmd = command + " >" + out_ + " 2>" + err_ + " & echo $! >" + pid_file;
  if (std::system(cmd.c_str()) != 0) return;
  pid_ = std::stoi(read_text(pid_file));
  for (int i = 0; i < 250 && pty_.empty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const std::string text = output();
    // A device path, or the link `emulate --link` keeps (" on /PATH").
    auto at = text.find("/dev/");
    if (const auto on = text.find(" on /"); at == std::string::npos && on != std::string::npos)
      at = on + 4;
    const auto end = at == std::string::npos ? at : text.find_first_of(" \n", at);
    if (end != std::string::npos) pty_ = text.substr(at, end - at);
  }
}

pty_process::~pty_process() {
  if (pid_ <= 0) return;
  kill(pid_, SIGTERM);
  // Not our child (the shell started it): wait until it is gone.
  for (int i = 0; i < 100 && kill(pid_, 0) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

std::string pty_process::output() const {
  return read_text(out_) + read_text(err_);
}

}  // namespace gyroflip::test
