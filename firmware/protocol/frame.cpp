/// \file
/// \brief Frame encoder and byte-at-a-time decoder (see frame.hpp).
#include "frame.hpp"

namespace gyroflip::protocol {

namespace detail {

size_t seal_raw(uint8_t type, uint16_t seq, size_t len, uint8_t* raw) {
  uint8_t extra = 0;
  if (len > max_payload || !crc_extra_of(type, extra)) return 0;
  raw[0] = protocol_version;
  raw[1] = type;
  raw[2] = static_cast<uint8_t>(seq & 0xFFu);
  raw[3] = static_cast<uint8_t>(seq >> 8);
  raw[4] = static_cast<uint8_t>(len);
  const size_t body = header_bytes + len;
  const uint16_t crc = crc16_byte(crc16(raw, body), extra);
  raw[body] = static_cast<uint8_t>(crc & 0xFFu);
  raw[body + 1] = static_cast<uint8_t>(crc >> 8);
  return body + crc_bytes;
}

size_t cobs_frame(size_t raw_len, uint8_t* out, size_t cap) {
  if (raw_len == 0 || raw_len > max_frame || cap < stage + cobs_max_encoded(raw_len) + 1) return 0;
  const size_t n = cobs_encode(out + stage, raw_len, out, cap - 1);
  if (n == 0) return 0;
  out[n] = 0;
  return n + 1;
}

size_t seal_frame(uint8_t type, uint16_t seq, size_t len, uint8_t* out, size_t cap) {
  if (cap < max_wire) return 0;
  return cobs_frame(seal_raw(type, seq, len, out + stage), out, cap);
}

}  // namespace detail

size_t encode_frame(uint8_t type, uint16_t seq, const uint8_t* payload, size_t len, uint8_t* out,
                    size_t cap) {
  if (len > max_payload || cap < max_wire) return 0;
  uint8_t* at = out + detail::stage + header_bytes;
  for (size_t i = 0; i < len; ++i) at[i] = payload[i];
  return detail::seal_frame(type, seq, len, out, cap);
}

}  // namespace gyroflip::protocol
