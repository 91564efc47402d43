/// \file
/// \brief Terminal progress line (see progress.hpp).
#include "progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <utility>

namespace gyroflip::app {
namespace {
constexpr std::uint32_t check_every = 4096;  // clock reads are ~20 ns; keep them out of hot loops
constexpr auto redraw_period = std::chrono::milliseconds(100);
constexpr int bar_width = 30;
}  // namespace

progress::progress(std::string label, std::uint64_t total)
    : progress(std::move(label), total, ::isatty(STDERR_FILENO) == 1) {}

progress::progress(std::string label, std::uint64_t total, bool enabled)
    : label_(std::move(label)),
      total_(std::max<std::uint64_t>(total, 1)),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

progress::~progress() {
  finish();
}

void progress::update(std::uint64_t done) {
  // Read the clock every check_every calls (hot loops) or when 1 % more is done (coarse steps).
  if (!enabled_) return;
  if (++calls_ % check_every != 0 && done < total_ && (done - last_done_) * 100 < total_) return;
  last_done_ = done;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < redraw_period && done < total_) return;
  last_ = now;
  draw(done);
}

void progress::draw(std::uint64_t done) {
  const double frac = std::min(1.0, static_cast<double>(done) / static_cast<double>(total_));
  const int filled = static_cast<int>(frac * bar_width);
  const double elapsed_s = std::chrono::duration<double>(last_ - start_).count();
  const double eta_s = frac > 0.0 ? elapsed_s * (1.0 - frac) / frac : 0.0;
  std::fprintf(stderr, "\r%s [%-*.*s] %5.1f%%  eta %.0f s ", label_.c_str(), bar_width, filled,
               "##############################", 100.0 * frac, eta_s);
  std::fflush(stderr);
  drawn_ = true;
}

void progress::finish() {
  if (!drawn_) return;
  std::fprintf(stderr, "\r%*s\r", static_cast<int>(label_.size()) + bar_width + 30, "");
  std::fflush(stderr);
  drawn_ = false;
}

progress_fn per_mille(progress& bar) {
  return [&bar](std::size_t done, std::size_t total) {
    bar.update(done * 1000 / std::max<std::size_t>(total, 1));
  };
}

}  // namespace gyroflip::app
