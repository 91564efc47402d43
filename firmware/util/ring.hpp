/// \file
/// \brief A fixed byte ring (no allocation): the firmware's transmit queue. Frames go in whole
/// or not at all, so the UART never sends half a frame.
#pragma once

#include <stddef.h>
#include <stdint.h>

namespace gyroflip::fw {

template <size_t N>
class byte_ring {
 public:
  [[nodiscard]] size_t size() const { return count_; }
  [[nodiscard]] size_t free() const { return N - count_; }
  /// Appends all `n` bytes, or none when they do not fit.
  bool push(const uint8_t* p, size_t n) {
    if (n > free()) return false;
    size_t at = wrap(head_ + count_);
    for (size_t i = 0; i < n; ++i) {
      buf_[at] = p[i];
      if (++at == N) at = 0;
    }
    count_ += n;
    return true;
  }
  /// The oldest byte, without taking it; false when empty.
  bool peek(uint8_t* b) const { return peek(0, b); }
  /// The `k`-th oldest byte (0: the oldest), without taking it; false when there are not k + 1.
  bool peek(size_t k, uint8_t* b) const {
    if (k >= count_) return false;
    *b = buf_[wrap(head_ + k)];
    return true;
  }
  void pop() {
    if (count_ == 0) return;
    head_ = wrap(head_ + 1);
    --count_;
  }
  /// The oldest bytes that lie one after the other in the ring (*p their first): how many.
  size_t span(const uint8_t** p) const {
    *p = buf_ + head_;
    return count_ < N - head_ ? count_ : N - head_;
  }
  /// Takes the `n` oldest bytes (all when there are fewer).
  void drop(size_t n) {
    if (n > count_) n = count_;
    head_ = wrap(head_ + n);
    count_ -= n;
  }

 private:
  // An index below 2N wrapped without a division (a runtime-helper call on the MSP430).
  static size_t wrap(size_t i) { return i >= N ? i - N : i; }
  uint8_t buf_[N] = {};
  size_t head_ = 0;
  size_t count_ = 0;
};

}  // namespace gyroflip::fw
