/// \file
/// \brief Running a helper program in its own process group, stopped with the caller on a
/// signal (run_program.hpp, gyroflip/report/helpers.hpp).
#include "run_program.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/report/helpers.hpp"

extern char** environ;  // NOLINT: POSIX, for execve

namespace gyroflip::report {

namespace {

// The process groups of the helpers running now (0: a free slot), for stop_helper_programs() in
// a signal handler: fixed slots of atomics, as io::atomic_file's registry of temporaries. Each
// helper leads its own group, so its own children (Chromium's renderers) are stopped with it.
constexpr std::size_t max_helpers = 8;
std::array<std::atomic<pid_t>, max_helpers> helpers{};  // NOLINT: process-wide by nature

int register_helper(pid_t pid) noexcept {
  for (std::size_t i = 0; i < helpers.size(); ++i) {
    pid_t free = 0;
    if (helpers[i].compare_exchange_strong(free, pid)) return static_cast<int>(i);
  }
  return -1;
}

// `name` as found on PATH (as execvp would), or empty.
std::string find_program(const std::string& name) {
  if (name.find('/') != std::string::npos) return name;
  const char* path = std::getenv("PATH");
  for (const auto& dir : text::split(path != nullptr ? path : "/usr/bin:/bin", ':')) {
    std::string candidate =
        (dir.text.empty() ? std::string(".") : std::string(dir.text)) + "/" + name;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
  }
  return {};
}

}  // namespace

void stop_helper_programs() noexcept {
  for (auto& h : helpers) {
    const pid_t pid = h.load();
    if (pid <= 0) continue;
    ::kill(-pid, SIGKILL);  // the group: the helper and what it started
    ::kill(pid, SIGKILL);   // the helper, should it not lead its group yet
    ::waitpid(pid, nullptr, 0);
  }
}

namespace detail {

result<program_run> run_program(const std::vector<std::string>& argv, const std::string& dir) {
  program_run run;
  const std::string exe = find_program(argv.front());
  if (exe.empty()) {
    run.exit_code = 127;
    return run;
  }
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));  // NOLINT: POSIX argv
  args.push_back(nullptr);
  int err_pipe[2];
  if (::pipe2(err_pipe, O_CLOEXEC) != 0)
    return runtime_error(fmt::format("cannot run {}: no pipe", argv.front()));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    // The child, until exec: async-signal-safe calls only (the parent may have threads). Its own
    // process group, killed with the caller should the caller die first (even by SIGKILL, which
    // no handler sees), with default signal handling (the caller ignores SIGPIPE).
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the caller is gone already
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::signal(SIGPIPE, SIG_DFL);
    if (::chdir(dir.c_str()) != 0) ::_exit(126);
    ::dup2(err_pipe[1], 2);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, 1);
    ::execve(exe.c_str(), args.data(), environ);
    ::_exit(127);
  }
  ::close(err_pipe[1]);
  if (pid < 0) {
    ::close(err_pipe[0]);
    return runtime_error(fmt::format("cannot run {}: {}", argv.front(), std::strerror(errno)));
  }
  ::setpgid(pid, pid);  // also from here: whichever runs first, the group exists after it
  const int slot = register_helper(pid);
  std::array<char, 4096> buf{};
  for (ssize_t got = 0; (got = ::read(err_pipe[0], buf.data(), buf.size())) != 0;) {
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) break;
    if (run.messages.size() < 2000) run.messages.append(buf.data(), static_cast<std::size_t>(got));
  }
  ::close(err_pipe[0]);
  int wstatus = 0;
  while (::waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {
  }
  if (slot >= 0) helpers[static_cast<std::size_t>(slot)].store(0);
  run.exit_code = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
  return run;
}

}  // namespace detail
}  // namespace gyroflip::report
