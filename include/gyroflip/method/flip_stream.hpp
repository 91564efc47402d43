/// \file
/// \brief Streaming rows -> cycles: feed rows one at a time, get each cycle as soon as it is
/// final. Gives the same numbers as `extract_dwells` + `pair_cycles` (tested bit for bit).
/// The live recorder and the firmware use this form.
#pragma once

#include <cstddef>

#include "gyroflip/method/dwells.hpp"
#include "gyroflip/method/pairing.hpp"

namespace gyroflip::method {

class flip_stream {
 public:
  explicit flip_stream(pairing p) noexcept : cycles_(p) {}

  /// Adds a validated row; calls `sink(const cycle&)` for each cycle it completes.
  template <class Sink>
  void push(const row& r, Sink&& sink) {
    if (auto d = dwells_.push(r)) take(*d, sink);
  }

  /// End of data: emits the cycles still held back.
  template <class Sink>
  void flush(Sink&& sink) {
    if (auto d = dwells_.flush()) take(*d, sink);
    if (auto c = cycles_.flush()) sink(*c);
  }

  /// Dwells seen at 0 deg and at 180 deg so far.
  [[nodiscard]] std::size_t dwells_at_0() const noexcept { return n0_; }
  [[nodiscard]] std::size_t dwells_at_180() const noexcept { return n180_; }

 private:
  template <class Sink>
  void take(const dwell& d, Sink& sink) {
    (d.sign > 0 ? n0_ : n180_) += 1;
    if (auto c = cycles_.push(d)) sink(*c);
  }
  dwell_builder dwells_;
  cycle_builder cycles_;
  std::size_t n0_ = 0;
  std::size_t n180_ = 0;
};

}  // namespace gyroflip::method
