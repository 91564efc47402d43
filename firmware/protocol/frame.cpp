/// \file
/// \brief Frame encoder and byte-at-a-time decoder (see frame.hpp).
#include "frame.hpp"

namespace gyroflip::protocol {

namespace detail {

size_t seal_frame(uint8_t type, uint16_t seq, size_t len, uint8_t* out, size_t cap) {
  uint8_t extra = 0;
  if (len > max_payload || cap < max_wire || !crc_extra_of(type, extra)) return 0;
  uint8_t* raw = out + stage;
  raw[0] = protocol_version;
  raw[1] = type;
  raw[2] = static_cast<uint8_t>(seq & 0xFFu);
  raw[3] = static_cast<uint8_t>(seq >> 8);
  raw[4] = static_cast<uint8_t>(len);
  const size_t body = header_bytes + len;
  const uint16_t crc = crc16_byte(crc16(raw, body), extra);
  raw[body] = static_cast<uint8_t>(crc & 0xFFu);
  raw[body + 1] = static_cast<uint8_t>(crc >> 8);
  const size_t n = cobs_encode(raw, body + crc_bytes, out, cap - 1);
  if (n == 0) return 0;
  out[n] = 0;
  return n + 1;
}

}  // namespace detail

size_t encode_frame(uint8_t type, uint16_t seq, const uint8_t* payload, size_t len, uint8_t* out,
                    size_t cap) {
  if (len > max_payload || cap < max_wire) return 0;
  uint8_t* at = out + detail::stage + header_bytes;
  for (size_t i = 0; i < len; ++i) at[i] = payload[i];
  return detail::seal_frame(type, seq, len, out, cap);
}

bool frame_decoder::push(uint8_t b) {
  if (b != 0) {
    if (n_ < max_wire) {
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

bool frame_decoder::finish() {
  if (overflowed_) {
    ++counts_.too_long;
    return false;
  }
  if (n_ == 0) return false;  // back-to-back delimiters: no frame, nothing lost
  const long len = cobs_decode(buf_, n_, buf_, max_frame);
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
  if (!crc_extra_of(buf_[1], extra)) {
    ++counts_.unknown_type;
    return false;
  }
  const size_t body = size - crc_bytes;
  const uint16_t crc = crc16_byte(crc16(buf_, body), extra);
  if ((crc & 0xFFu) != buf_[body] || (crc >> 8) != buf_[body + 1]) {
    ++counts_.crc_errors;
    return false;
  }
  ++counts_.good;
  const auto seq = static_cast<uint16_t>(buf_[2] | (buf_[3] << 8));
  if (have_seq_) {
    const auto gap = static_cast<uint16_t>(seq - last_seq_);
    if (gap == 0 || gap >= 0x8000u) {  // the same frame again, or one from the recent past
      ++counts_.duplicates;
      if (!deliver_repeats_) return false;
    } else {
      counts_.missing += gap - 1u;
    }
  }
  have_seq_ = true;
  last_seq_ = seq;
  frame_ = frame{buf_[1], seq, buf_ + header_bytes, buf_[4]};
  return true;
}

}  // namespace gyroflip::protocol
