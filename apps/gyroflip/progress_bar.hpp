/// \file
/// \brief The CLI's progress line on stderr for long work, shown only when stderr is a terminal.
/// The library never draws it: it reports through `gyroflip::progress_fn` (core/progress.hpp).
///
/// Piped or redirected runs (CI, tests, scripts) stay silent. Redraws at most ~10 times a
/// second, so calling `update()` in a hot loop costs one clock read every `check_every` calls.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include "gyroflip/core/progress.hpp"

namespace gyroflip::app {

class progress {
 public:
  /// `label` is printed before the bar; `total` is the amount of work (any unit, > 0).
  progress(std::string label, std::uint64_t total);
  /// Forces the bar on or off (tests); by default it is on iff stderr is a TTY.
  progress(std::string label, std::uint64_t total, bool enabled);
  ~progress();
  progress(const progress&) = delete;
  progress& operator=(const progress&) = delete;

  /// Reports that `done` units of `total` are complete.
  void update(std::uint64_t done);
  /// Clears the line (called by the destructor too).
  void finish();
  [[nodiscard]] bool enabled() const noexcept { return enabled_; }

 private:
  void draw(std::uint64_t done);
  std::string label_;
  std::uint64_t total_;
  bool enabled_;
  bool drawn_ = false;
  std::uint32_t calls_ = 0;
  std::uint64_t last_done_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_;
};

/// The library's progress callback drawing on `bar` (made with a total of 1000): done of total
/// units become per mille.
[[nodiscard]] progress_fn per_mille(progress& bar);

}  // namespace gyroflip::app
