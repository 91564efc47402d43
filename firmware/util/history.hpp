/// \file
/// \brief The retransmit history (docs/PROTOCOL.md, RESEND): the device's most recent frames
/// before COBS, each as [length][frame], oldest first, the oldest dropped when a new one needs
/// room. Looked up by sequence number (bytes 2-3 of a frame). No allocation.
#pragma once

#include <stddef.h>
#include <stdint.h>

namespace gyroflip::fw {

template <size_t N>
class frame_history {
 public:
  static_assert(N >= 32 && N <= 65535);
  /// Keeps a copy of frame `f` (`len` bytes, at most 255), dropping the oldest as needed.
  void store(const uint8_t* f, size_t len) {
    if (len < 5 || len > 255 || len + 1 > N) return;
    while (N - used_ < len + 1) drop_oldest();
    put(used_, static_cast<uint8_t>(len));
    for (size_t i = 0; i < len; ++i) put(used_ + 1 + i, f[i]);
    used_ += len + 1;
    ++frames_;
  }
  /// Copies the frame with sequence number `seq` to `out` (capacity `cap`); its length, or 0
  /// when it is no longer (or never was) held.
  [[nodiscard]] size_t find(uint16_t seq, uint8_t* out, size_t cap) const {
    for (size_t e = 0; e < used_;) {
      const size_t len = get(e);
      if (seq_at(e) == seq) {
        if (len > cap) return 0;
        for (size_t i = 0; i < len; ++i) out[i] = get(e + 1 + i);
        return len;
      }
      e += len + 1;
    }
    return 0;
  }
  /// The sequence number of the oldest frame held (0 when empty: see `empty`).
  [[nodiscard]] uint16_t oldest_seq() const { return used_ == 0 ? 0 : seq_at(0); }
  [[nodiscard]] bool empty() const { return used_ == 0; }
  [[nodiscard]] size_t frames() const { return frames_; }
  [[nodiscard]] static constexpr size_t capacity() { return N; }

 private:
  // Index i (< N) past the head, wrapped without a division (a helper call on the MSP430).
  [[nodiscard]] size_t at(size_t i) const {
    const size_t j = head_ + i;
    return j >= N ? j - N : j;
  }
  [[nodiscard]] uint8_t get(size_t i) const { return buf_[at(i)]; }
  void put(size_t i, uint8_t v) { buf_[at(i)] = v; }
  [[nodiscard]] uint16_t seq_at(size_t e) const {
    return static_cast<uint16_t>(get(e + 3) | (get(e + 4) << 8));
  }
  void drop_oldest() {
    const size_t len = get(0) + size_t{1};
    head_ = at(len);
    used_ -= len;
    --frames_;
  }
  uint8_t buf_[N] = {};
  size_t head_ = 0;  // the oldest entry's length byte
  size_t used_ = 0;
  size_t frames_ = 0;
};

}  // namespace gyroflip::fw
