/// \file
/// \brief Running a helper program with posix_spawn (run_program.hpp).
#include "run_program.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

extern char** environ;  // NOLINT: POSIX, for posix_spawn

namespace gyroflip::report::detail {

result<program_run> run_program(const std::vector<std::string>& argv, const std::string& dir) {
  int err_pipe[2];
  if (::pipe2(err_pipe, O_CLOEXEC) != 0)
    return runtime_error(fmt::format("cannot run {}: no pipe", argv.front()));
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addchdir_np(&fa, dir.c_str());
  posix_spawn_file_actions_adddup2(&fa, err_pipe[1], 2);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));  // NOLINT: POSIX argv
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = ::posix_spawnp(&pid, argv.front().c_str(), &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  ::close(err_pipe[1]);
  program_run run;
  std::array<char, 4096> buf{};
  for (ssize_t got = 0; (got = ::read(err_pipe[0], buf.data(), buf.size())) != 0;) {
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) break;
    if (run.messages.size() < 2000) run.messages.append(buf.data(), static_cast<std::size_t>(got));
  }
  ::close(err_pipe[0]);
  if (rc == ENOENT) {
    run.exit_code = 127;
    return run;
  }
  if (rc != 0)
    return runtime_error(fmt::format("cannot run {}: {}", argv.front(), std::strerror(rc)));
  int wstatus = 0;
  while (::waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {
  }
  run.exit_code = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
  return run;
}

}  // namespace gyroflip::report::detail
