/// \file
/// \brief The stop flag set by a signal (stop_signal.hpp).
#include "stop_signal.hpp"

#include <csignal>

namespace gyroflip::app {

namespace {

std::atomic<bool> stop_flag{false};
static_assert(std::atomic<bool>::is_always_lock_free);  // safe to set in a signal handler

extern "C" void on_stop_signal(int) {
  stop_flag.store(true);
}

}  // namespace

const std::atomic<bool>& catch_stop_signals(std::initializer_list<int> signals) {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sa.sa_flags = SA_RESTART;  // as signal(2) does: slow calls resume, polls return EINTR
  sigemptyset(&sa.sa_mask);
  for (const int sig : signals) sigaction(sig, &sa, nullptr);
  return stop_flag;
}

}  // namespace gyroflip::app
