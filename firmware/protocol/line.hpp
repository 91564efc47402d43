/// \file
/// \brief The line code of protocol v2 (docs/PROTOCOL.md, "Line code"): every byte of the COBS
/// stream goes on the wire as two bytes, its high nibble then its low nibble, each as a codeword
/// of the extended Hamming [8,4,4] code. A receiver corrects any single bit error in a wire byte
/// and detects any double one, so a frame of n COBS bytes survives a bit error rate p with
/// probability about (1 - 28 p^2)^(2n) instead of (1 - p)^(8n): at p = 1e-2 a DWELL arrives
/// whole 73 % of the time instead of 1 %; retransmission does the rest.
///
/// A frame ends with a run of zero wire bytes (codewords of the nibble 0) instead of COBS's 0x00:
/// COBS bytes are never 0x00, so at most two zero nibbles follow each other inside a frame, and
/// a run of four or more is a frame boundary wherever the receiver stood. The run is 4 bytes
/// long after a frame whose last nibble is not 0, and 10 after one whose last nibble is 0, so
/// that the run's length tells the receiver which of its zeros belongs to the frame before it
/// and which to the one after: it re-anchors which nibble is high after a lost wire byte. A
/// host also puts a run of 4 before each command (line noise before it then never joins it).
/// Freestanding: no allocation, tables computed at compile time.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "frame.hpp"

namespace gyroflip::protocol {

/// The codeword of a nibble: bits 0-3 the nibble d0..d3, bits 4-7 the parities
/// p0 = d1^d2^d3, p1 = d0^d2^d3, p2 = d0^d1^d3, p3 = d0^d1^d2 (the extended Hamming code in
/// systematic form: every nonzero codeword has weight 4 or 8, so any two differ in >= 4 bits).
[[nodiscard]] constexpr uint8_t hamming84_codeword(uint8_t nibble) {
  const unsigned d0 = nibble & 1u, d1 = (nibble >> 1) & 1u, d2 = (nibble >> 2) & 1u,
                 d3 = (nibble >> 3) & 1u;
  const unsigned p0 = d1 ^ d2 ^ d3, p1 = d0 ^ d2 ^ d3, p2 = d0 ^ d1 ^ d3, p3 = d0 ^ d1 ^ d2;
  return static_cast<uint8_t>((nibble & 0x0Fu) | (p0 << 4) | (p1 << 5) | (p2 << 6) | (p3 << 7));
}
namespace detail {
struct hamming84_codewords {
  uint8_t v[16];
};
constexpr hamming84_codewords make_hamming84_codewords() {
  hamming84_codewords t{};
  for (uint8_t n = 0; n < 16; ++n) t.v[n] = hamming84_codeword(n);
  return t;
}
// The 16 codewords as a table (16 bytes of flash): a device codes every byte it sends, and the
// formula's shifts cost the MSP430 ~100 cycles a nibble, a fifth of the line's byte time.
inline constexpr hamming84_codewords hamming84_words = make_hamming84_codewords();
}  // namespace detail
/// The codeword of `nibble` (its low 4 bits).
[[nodiscard]] constexpr uint8_t hamming84_encode(uint8_t nibble) {
  return detail::hamming84_words.v[nibble & 0x0Fu];
}

/// What a wire byte decodes to: the nibble (0..15), with hamming84_corrected set when one bit
/// was wrong, or hamming84_error when two or more were (detected, not correctable).
inline constexpr uint8_t hamming84_corrected = 0x10;
inline constexpr uint8_t hamming84_error = 0xFF;

namespace detail {
struct hamming84_table {
  uint8_t v[256] = {};
};
[[nodiscard]] constexpr unsigned popcount8(unsigned x) {
  unsigned n = 0;
  for (; x != 0; x &= x - 1) ++n;
  return n;
}
[[nodiscard]] constexpr hamming84_table make_hamming84_table() {
  hamming84_table t;
  for (unsigned b = 0; b < 256; ++b) {
    t.v[b] = hamming84_error;
    for (uint8_t n = 0; n < 16; ++n) {
      const unsigned d = popcount8(b ^ hamming84_encode(n));
      if (d == 0) t.v[b] = n;
      if (d == 1) t.v[b] = static_cast<uint8_t>(n | hamming84_corrected);
    }
  }
  return t;
}
inline constexpr hamming84_table hamming84 = make_hamming84_table();
}  // namespace detail

/// Decodes one wire byte (a table lookup: 256 bytes of flash on a device).
[[nodiscard]] constexpr uint8_t hamming84_decode(uint8_t wire) {
  return detail::hamming84.v[wire];
}

static_assert(hamming84_encode(0) == 0 && hamming84_decode(0) == 0);
static_assert(hamming84_decode(hamming84_encode(9) ^ 0x40u) == (9 | hamming84_corrected));
static_assert(hamming84_decode(hamming84_encode(9) ^ 0x41u) == hamming84_error);

/// Wire bytes per byte of the COBS stream.
inline constexpr size_t line_expansion = 2;
/// Zero wire bytes after a frame: 4 when its last nibble is not 0, 10 when it is; 4 before a
/// host's command.
inline constexpr size_t run_after_nonzero = 4;
inline constexpr size_t run_after_zero = 10;
inline constexpr size_t run_before_command = 4;
/// The run after a frame whose last COBS byte is `last`.
[[nodiscard]] constexpr size_t run_after(uint8_t last) {
  return (last & 0x0Fu) == 0 ? run_after_zero : run_after_nonzero;
}

/// Wire bytes of a frame with `payload` payload bytes (at most): its COBS bytes, each as two,
/// and the longest run after it.
[[nodiscard]] constexpr size_t line_bytes(size_t payload) {
  return line_expansion * cobs_max_encoded(header_bytes + payload + crc_bytes) + run_after_zero;
}

/// The two wire bytes of one byte of the COBS stream (high nibble first).
inline void line_encode(uint8_t b, uint8_t out[2]) {
  out[0] = hamming84_encode(static_cast<uint8_t>(b >> 4));
  out[1] = hamming84_encode(static_cast<uint8_t>(b & 0x0Fu));
}

/// Message `m` as wire bytes in `out` (capacity `cap` >= line_bytes(max_payload) + 4): the
/// frame, its delimiters and the line code; with `lead`, a delimiter run before it too, so that
/// line noise before the frame can never join it (a host sends its commands so). Returns the
/// bytes to send, or 0. For hosts and tests; a device queues the COBS stream and codes each byte
/// as the UART takes it.
template <class M>
[[nodiscard]] size_t encode_wire(const M& m, uint16_t seq, uint8_t* out, size_t cap,
                                 bool lead = false) {
  uint8_t cobs[max_wire];
  size_t n = encode_message(m, seq, cobs, sizeof cobs);
  if (n < 2) return 0;
  --n;  // the COBS stream's own 0x00: the line's run takes its place
  const size_t before = lead ? run_before_command : 0;
  const size_t after = run_after(cobs[n - 1]);
  if (cap < before + line_expansion * n + after) return 0;
  size_t k = 0;
  for (; k < before; ++k) out[k] = 0;  // the codeword of the nibble 0 is 0x00
  for (size_t i = 0; i < n; ++i, k += line_expansion) line_encode(cobs[i], out + k);
  for (size_t i = 0; i < after; ++i) out[k++] = 0;
  return k;
}
/// Room encode_wire needs for any message, with a leading run.
inline constexpr size_t max_wire_bytes = line_bytes(max_payload) + run_before_command;

/// What the line decoder saw.
template <class C = uint32_t>
struct basic_line_counts {
  C corrected = 0;      ///< wire bytes with one bit wrong, corrected
  C uncorrectable = 0;  ///< wire bytes with two or more bits wrong (their frame is lost)
  C realigned = 0;      ///< nibble phase found wrong at a frame boundary (a lost byte)
};
using line_counts = basic_line_counts<>;

/// Wire bytes in, frames out: the line decoder (above) feeding a frame decoder of `Cap` bytes.
/// A frame is handed out as soon as its delimiter run is 4 nibbles long. Counts are of type `C`
/// (a device counts in 16 bits: RAM).
template <size_t Cap, class C = uint32_t>
class basic_stream_decoder {
 public:
  constexpr basic_stream_decoder() = default;
  /// `deliver_repeats`: as basic_frame_decoder's.
  constexpr explicit basic_stream_decoder(bool deliver_repeats) : frames_(deliver_repeats) {}

  /// Takes one wire byte; true when it completed a new valid frame (then `current()`).
  [[nodiscard]] bool push(uint8_t wire) {
    const uint8_t d = hamming84_decode(wire);
    if (d == hamming84_error) {
      ++line_.uncorrectable;
    } else if ((d & hamming84_corrected) != 0) {
      ++line_.corrected;
    }
    // An uncorrectable byte stands for some nonzero nibble: it keeps the nibble count (and so
    // the alignment), and the frame's CRC rejects the frame.
    const uint8_t n = d == hamming84_error ? 0x0F : static_cast<uint8_t>(d & 0x0Fu);
    if (n == 0) {
      if (zeros_ == 0) started_lo_ = lo_;
      // A long idle run of zeros: the count only matters modulo 4 beyond 16, so it stays in
      // 249..252 (253 counts as 249).
      zeros_ = static_cast<uint8_t>(zeros_ < 252 ? zeros_ + 1 : zeros_ - 3);
      if (zeros_ != 4) return false;
      // A frame boundary: complete the last byte with the run's first zero if that was a low
      // nibble, then end the frame.
      ended_ = true;
      if (started_lo_) static_cast<void>(nibble(0));
      lo_ = false;
      return frames_.push(0);
    }
    const bool got = zeros_ != 0 && end_of_run();
    return nibble(n) || got;
  }
  [[nodiscard]] const frame& current() const { return frames_.current(); }
  [[nodiscard]] const basic_decoder_counts<C>& counts() const { return frames_.counts(); }
  [[nodiscard]] const basic_line_counts<C>& line() const { return line_; }
  /// The frame layer (its sequence history, the header of its last bad frame).
  [[nodiscard]] basic_frame_decoder<Cap, C>& frames() { return frames_; }
  [[nodiscard]] const basic_frame_decoder<Cap, C>& frames() const { return frames_; }

 private:
  bool nibble(uint8_t n) {
    if (!lo_) {
      hi_ = n;
      lo_ = true;
      return false;
    }
    lo_ = false;
    return frames_.push(static_cast<uint8_t>((hi_ << 4) | n));
  }

  // A run of zero nibbles ended. Shorter than 4: they were data. Otherwise the frame already
  // ended at the 4th; the run's length Z = x + R + y says where the next frame's first byte
  // starts: x = 1 when the last frame's low nibble 0 began the run, R = 4 or 10 for x = 0 or 1
  // (4 more before a command), y = 1 when the next frame's high nibble 0 ends it. So Z in
  // {4, 5, 8, 9} has x = 0, Z in {11, 12, 15, 16} has x = 1, and y = (Z - x) mod 2. An x that
  // differs from where the run started means a wire byte was lost before it: the nibbles are
  // realigned here. Other lengths (idle zeros) keep the reading from where the run started.
  bool end_of_run() {
    bool got = false;
    if (!ended_) {
      for (uint8_t i = 0; i < zeros_; ++i) got = nibble(0) || got;
    } else {
      unsigned x = started_lo_ ? 1u : 0u;
      if (zeros_ == 4 || zeros_ == 5 || zeros_ == 8 || zeros_ == 9) {
        if (x != 0) ++line_.realigned;
        x = 0;
      } else if (zeros_ == 11 || zeros_ == 12 || zeros_ == 15 || zeros_ == 16) {
        if (x != 1) ++line_.realigned;
        x = 1;
      }
      lo_ = false;
      if ((zeros_ - x) % 2u == 1) static_cast<void>(nibble(0));
    }
    zeros_ = 0;
    ended_ = false;
    return got;
  }

  basic_frame_decoder<Cap, C> frames_;
  basic_line_counts<C> line_;
  uint8_t zeros_ = 0;        // zero nibbles in the current run (saturating)
  bool lo_ = false;          // the next nibble is a low nibble
  uint8_t hi_ = 0;           // the pending high nibble
  bool ended_ = false;       // the current run already ended a frame
  bool started_lo_ = false;  // the run started at a low nibble
};

/// The stream decoder of any frame (a host's).
using stream_decoder = basic_stream_decoder<max_wire>;

}  // namespace gyroflip::protocol
