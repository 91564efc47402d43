/// \file
/// \brief The retransmit history (docs/PROTOCOL.md, RESEND): the device's most recent frames
/// before COBS, each as [length][frame], oldest first, the oldest dropped when a new one needs
/// room. Looked up by sequence number (bytes 2-3 of a frame). A frame a RESEND asked for is
/// marked (the length byte's top bit) until it goes out again: the device sends the marked frames
/// a few per main-loop pass (docs/FIRMWARE.md), with no list of its own. No allocation.
#pragma once

#include <stddef.h>
#include <stdint.h>

namespace gyroflip::fw {

template <size_t N>
class frame_history {
 public:
  static_assert(N >= 32 && N <= 65535);
  /// The longest frame kept (the length byte's low 7 bits; the top bit is the mark).
  static constexpr size_t max_frame = 127;
  /// Keeps a copy of frame `f` (`len` bytes, at most max_frame), dropping the oldest as needed.
  void store(const uint8_t* f, size_t len) {
    if (len < 5 || len > max_frame || len + 1 > N) return;
    while (N - used_ < len + 1) drop_oldest();
    put(used_, static_cast<uint8_t>(len));
    for (size_t i = 0; i < len; ++i) put(used_ + 1 + i, f[i]);
    used_ += len + 1;
    ++frames_;
  }
  /// Copies the frame with sequence number `seq` to `out` (capacity `cap`); its length, or 0
  /// when it is no longer (or never was) held.
  [[nodiscard]] size_t find(uint16_t seq, uint8_t* out, size_t cap) const {
    const size_t e = entry_of(seq);
    if (e == used_) return 0;
    return copy(e, out, cap);
  }
  /// Marks the frame with sequence number `seq` for sending again; false when it is not held.
  bool mark(uint16_t seq) {
    const size_t e = entry_of(seq);
    if (e == used_) return false;
    put(e, static_cast<uint8_t>(get(e) | mark_bit));
    return true;
  }
  /// The length of the oldest marked frame, or 0 when none is marked.
  [[nodiscard]] size_t marked() const {
    const size_t e = first_marked();
    return e == used_ ? 0 : length(e);
  }
  /// Copies the oldest marked frame to `out` (capacity `cap`) and unmarks it; its length, or 0
  /// when none is marked (or it does not fit `cap`: then it is unmarked too).
  size_t take_marked(uint8_t* out, size_t cap) {
    const size_t e = first_marked();
    if (e == used_) return 0;
    put(e, static_cast<uint8_t>(length(e)));
    return copy(e, out, cap);
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
  static constexpr uint8_t mark_bit = 0x80;
  [[nodiscard]] size_t length(size_t e) const { return get(e) & (mark_bit - 1u); }
  // The entry (offset of its length byte) of frame `seq`, or used_ when it is not held.
  [[nodiscard]] size_t entry_of(uint16_t seq) const {
    size_t e = 0;
    while (e < used_ && seq_at(e) != seq) e += length(e) + 1;
    return e < used_ ? e : used_;
  }
  [[nodiscard]] size_t first_marked() const {
    size_t e = 0;
    while (e < used_ && (get(e) & mark_bit) == 0) e += length(e) + 1;
    return e < used_ ? e : used_;
  }
  [[nodiscard]] size_t copy(size_t e, uint8_t* out, size_t cap) const {
    const size_t len = length(e);
    if (len > cap) return 0;
    for (size_t i = 0; i < len; ++i) out[i] = get(e + 1 + i);
    return len;
  }
  [[nodiscard]] uint16_t seq_at(size_t e) const {
    return static_cast<uint16_t>(get(e + 3) | (unsigned{get(e + 4)} << 8));
  }
  void drop_oldest() {
    const size_t len = length(0) + 1;
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
