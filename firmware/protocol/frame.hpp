/// \file
/// \brief Frames of the rig protocol (docs/PROTOCOL.md): header (version, type, 16-bit sequence,
/// payload length), payload, CRC-16/CCITT-FALSE over header and payload and then the message's
/// layout seed; the whole COBS-encoded and ended by 0x00. The decoder takes bytes one at a time
/// (a UART interrupt, a serial read), resynchronises at every 0x00, and counts every frame it
/// drops by reason and every sequence gap. No allocation: one buffer of the largest frame each.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "cobs.hpp"
#include "messages.hpp"
#include "status.hpp"

namespace gyroflip::protocol {

inline constexpr uint8_t protocol_version = 2;
inline constexpr size_t header_bytes = 5;  // version, type, seq (LE), payload length
inline constexpr size_t crc_bytes = 2;
inline constexpr size_t max_payload = 200;
inline constexpr size_t max_frame = header_bytes + max_payload + crc_bytes;
/// Bytes on the wire of the largest frame: COBS-encoded plus the 0x00 delimiter.
inline constexpr size_t max_wire = cobs_max_encoded(max_frame) + 1;

/// Bytes on the wire of a frame with `payload` payload bytes (at most: COBS adds one byte per
/// 254, plus the code byte and the delimiter).
[[nodiscard]] constexpr size_t wire_bytes(size_t payload) {
  return cobs_max_encoded(header_bytes + payload + crc_bytes) + 1;
}

namespace detail {
/// Where a frame is staged inside the output buffer before it is COBS-encoded in place.
inline constexpr size_t stage = cobs_max_encoded(max_frame) - max_frame;
/// Writes header and CRC around the `len` payload bytes at raw + header_bytes: the frame before
/// COBS (what a device keeps for retransmission). Returns its length, or 0 (payload too long,
/// unknown type).
[[nodiscard]] size_t seal_raw(uint8_t type, uint16_t seq, size_t len, uint8_t* raw);
/// COBS-encodes the `raw_len`-byte frame staged at out + stage into out, in place, and appends
/// the delimiter; returns the bytes to send, or 0.
[[nodiscard]] size_t cobs_frame(size_t raw_len, uint8_t* out, size_t cap);
/// Both: the bytes to send, or 0.
[[nodiscard]] size_t seal_frame(uint8_t type, uint16_t seq, size_t len, uint8_t* out, size_t cap);
}  // namespace detail

/// Encodes one frame into `out` (capacity `cap`, at least max_wire; `payload` outside it):
/// returns the bytes to send (delimiter included), or 0 (payload too long, buffer too small,
/// unknown type).
[[nodiscard]] size_t encode_frame(uint8_t type, uint16_t seq, const uint8_t* payload, size_t len,
                                  uint8_t* out, size_t cap);

/// Message `m` as a frame in `out` (capacity at least max_wire): its payload is written in
/// place, so a device needs no second buffer. Returns the bytes to send, or 0.
template <class M>
[[nodiscard]] size_t encode_message(const M& m, uint16_t seq, uint8_t* out, size_t cap) {
  if (cap < max_wire) return 0;
  writer w{out + detail::stage + header_bytes, max_payload};
  m.put(w);
  if (!w.ok) return 0;
  return detail::seal_frame(static_cast<uint8_t>(M::type), seq, w.n, out, cap);
}

/// A decoded frame (valid until the next push).
struct frame {
  uint8_t type = 0;
  uint16_t seq = 0;
  const uint8_t* payload = nullptr;
  size_t length = 0;
  /// Decodes the payload as message M; false when the type or the length is not M's.
  template <class M>
  [[nodiscard]] bool as(M& m) const {
    if (type != static_cast<uint8_t>(M::type)) return false;
    reader r{payload, length};
    m.get(r);
    return r.done();
  }
};

/// Counts of a decoder. Every delimiter that ends at least one byte adds exactly one to `good`
/// or to one of the bad counts; `duplicates` (good frames not handed out again) and `missing`
/// come from the sequence numbers of good frames.
template <class C = uint32_t>
struct basic_decoder_counts {
  C good = 0;                   ///< valid frames (well formed, CRC correct), duplicates included
  C bad_cobs = 0;               ///< not valid COBS (corruption)
  C bad_length = 0;             ///< shorter than header and CRC, or the length field disagrees
  C bad_version = 0;            ///< another protocol version
  C unknown_type = 0;           ///< a message this version does not have
  C crc_errors = 0;             ///< CRC mismatch (corruption, or another layout of the message)
  C too_long = 0;               ///< more bytes than the largest frame before a delimiter
  C duplicates = 0;             ///< good frames that repeat an earlier sequence number
  C missing = 0;                ///< sequence numbers skipped (frames lost on the way)
  uint8_t foreign_version = 0;  ///< version byte of the last frame of another version (0: none)
  [[nodiscard]] uint32_t bad() const {
    return uint32_t{bad_cobs} + bad_length + bad_version + unknown_type + crc_errors + too_long;
  }
};
/// The counts in 32 bits (a host); a device may count in 16 (its STATUS carries 16 bits of each).
using decoder_counts = basic_decoder_counts<>;

/// Byte-at-a-time frame decoder holding frames of up to `Cap` bytes of COBS (a device that only
/// takes short commands keeps a small buffer). A frame whose sequence number repeats one of the
/// last 32768 (a retransmission, a duplicated packet) is counted and, by default, not handed out
/// again; a forward jump counts the skipped numbers as missing.
template <size_t Cap, class C = uint32_t>
class basic_frame_decoder {
 public:
  constexpr basic_frame_decoder() = default;
  /// `deliver_repeats`: hand out frames with a repeated or older sequence number too (counted
  /// as duplicates; the numbering continues from them). The device decodes commands this way,
  /// so a host program that restarts its numbering at 0 is still obeyed, and a host takes
  /// retransmitted frames this way.
  constexpr explicit basic_frame_decoder(bool deliver_repeats)
      : deliver_repeats_(deliver_repeats) {}
  /// Takes one byte; true when it completed a new valid frame (then `current()`).
  [[nodiscard]] bool push(uint8_t b) {
    if (b != 0) {
      if (n_ < Cap) {
        buf_[n_++] = b;
      } else {
        overflowed_ = true;  // keep discarding until the delimiter
      }
      return false;
    }
    const bool good = finish();
    n_ = 0;
    overflowed_ = false;
    return good;
  }
  [[nodiscard]] const frame& current() const { return frame_; }
  [[nodiscard]] const basic_decoder_counts<C>& counts() const { return counts_; }
  /// Forgets the sequence history (after a device reset: its numbering starts again).
  void reset_sequence() { have_seq_ = false; }
  /// The type and sequence number of the last frame dropped for its CRC (or an unknown type)
  /// whose header could be read, once, with why (status::crc_mismatch or not_supported): a
  /// device answers a damaged command with a NAK.
  [[nodiscard]] bool take_bad_header(uint8_t* type, uint16_t* seq, status* why) {
    if (!bad_pending_) return false;
    bad_pending_ = false;
    *type = bad_type_;
    *seq = bad_seq_;
    *why = bad_why_;
    return true;
  }

 private:
  bool finish() {
    if (overflowed_) {
      ++counts_.too_long;
      return false;
    }
    if (n_ == 0) return false;  // back-to-back delimiters: no frame, nothing lost
    const long len = cobs_decode(buf_, n_, buf_, Cap);
    if (len < 0) {
      ++counts_.bad_cobs;
      return false;
    }
    const auto size = static_cast<size_t>(len);
    if (size < header_bytes + crc_bytes || size != header_bytes + buf_[4] + crc_bytes) {
      ++counts_.bad_length;
      return false;
    }
    if (buf_[0] != protocol_version) {
      ++counts_.bad_version;
      counts_.foreign_version = buf_[0];
      return false;
    }
    uint8_t extra = 0;
    const bool known = crc_extra_of(buf_[1], extra);
    const size_t body = size - crc_bytes;
    const uint16_t crc = crc16_byte(crc16(buf_, body), extra);
    if (!known || (crc & 0xFFu) != buf_[body] || (crc >> 8) != buf_[body + 1]) {
      ++(known ? counts_.crc_errors : counts_.unknown_type);
      bad_pending_ = true;
      bad_type_ = buf_[1];
      bad_seq_ = static_cast<uint16_t>(buf_[2] | (buf_[3] << 8));
      bad_why_ = known ? status::crc_mismatch : status::not_supported;
      return false;
    }
    ++counts_.good;
    const auto seq = static_cast<uint16_t>(buf_[2] | (buf_[3] << 8));
    if (have_seq_) {
      const auto gap = static_cast<uint16_t>(seq - last_seq_);
      if (gap == 0 || gap >= 0x8000u) {  // the same frame again, or one from the recent past
        ++counts_.duplicates;
        if (!deliver_repeats_) return false;
        frame_ = frame{buf_[1], seq, buf_ + header_bytes, buf_[4]};
        return true;  // the numbering goes on from the newest frame
      }
      counts_.missing = static_cast<C>(counts_.missing + (gap - 1u));
    }
    have_seq_ = true;
    last_seq_ = seq;
    frame_ = frame{buf_[1], seq, buf_ + header_bytes, buf_[4]};
    return true;
  }

  uint8_t buf_[Cap] = {};
  size_t n_ = 0;
  bool overflowed_ = false;
  bool have_seq_ = false;
  bool deliver_repeats_ = false;
  uint16_t last_seq_ = 0;
  bool bad_pending_ = false;
  uint8_t bad_type_ = 0;
  uint16_t bad_seq_ = 0;
  status bad_why_ = status::ok;
  frame frame_{};
  basic_decoder_counts<C> counts_{};
};

/// The decoder of any frame (a host's).
using frame_decoder = basic_frame_decoder<max_wire>;

}  // namespace gyroflip::protocol
