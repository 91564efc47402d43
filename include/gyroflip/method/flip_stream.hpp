/// \file
/// \brief Streaming rows -> cycles: feed rows one at a time, get each cycle as soon as it is
/// final. Gives the same numbers as `extract_dwells` + `pair_cycles` (tested bit for bit).
/// The live recorder and the firmware use this form. The 0/180 demodulators use the two
/// positions of their flip_pair (method/flip_pair.hpp); rows at the table's other positions are
/// passed over as rows taken while the table turns.
#pragma once

#include <cstddef>

#include "gyroflip/method/dwells.hpp"
#include "gyroflip/method/pairing.hpp"

namespace gyroflip::method {

class flip_stream {
 public:
  explicit flip_stream(pairing p, flip_pair pair = {}) noexcept : pair_(pair), cycles_(p, pair) {}

  /// Adds a validated row; calls `sink(const cycle&)` for each cycle it completes.
  template <class Sink>
  void push(const row& r, Sink&& sink) {
    if (!pair_.holds(r.position)) {  // turning, or at a position not the pair's
      if (r.position != table_moving && r.position != last_off_) {
        ++off_pair_;
        last_off_ = r.position;
      }
      return;
    }
    last_off_ = table_moving;
    if (auto d = dwells_.push(r)) take(*d, sink);
  }

  /// End of data: emits the cycles still held back.
  template <class Sink>
  void flush(Sink&& sink) {
    if (auto d = dwells_.flush()) take(*d, sink);
    if (auto c = cycles_.flush()) sink(*c);
  }

  /// Dwells seen at the pair's +1 position (0 deg) and at its -1 position (180 deg) so far.
  [[nodiscard]] std::size_t dwells_at_0() const noexcept { return n0_; }
  [[nodiscard]] std::size_t dwells_at_180() const noexcept { return n180_; }
  /// Stays at positions other than the pair's so far (runs of rows at one such position).
  [[nodiscard]] std::size_t dwells_off_pair() const noexcept { return off_pair_; }
  [[nodiscard]] const flip_pair& pair() const noexcept { return pair_; }

 private:
  template <class Sink>
  void take(const dwell& d, Sink& sink) {
    (d.position == pair_.plus ? n0_ : n180_) += 1;
    if (auto c = cycles_.push(d)) sink(*c);
  }
  flip_pair pair_;
  int last_off_ = table_moving;
  std::size_t off_pair_ = 0;
  dwell_builder dwells_;
  cycle_builder cycles_;
  std::size_t n0_ = 0;
  std::size_t n180_ = 0;
};

}  // namespace gyroflip::method
