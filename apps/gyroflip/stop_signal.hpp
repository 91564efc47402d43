/// \file
/// \brief Long-running commands (`emulate`, `record`) end cleanly on a signal: the handler only
/// sets a flag that their loops poll, instead of main.cpp's default (remove temporaries, die).
#pragma once

#include <atomic>
#include <initializer_list>

namespace gyroflip::app {

/// Catches `signals` (SIGINT, SIGTERM, ...) with a handler that sets the returned flag.
[[nodiscard]] const std::atomic<bool>& catch_stop_signals(std::initializer_list<int> signals);

}  // namespace gyroflip::app
