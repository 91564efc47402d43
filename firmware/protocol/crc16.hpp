/// \file
/// \brief CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, not reflected, xorout 0; check value of
/// "123456789" = 0x29B1; Greg Cook's CRC catalogue), byte at a time with a 256-entry table in
/// flash (512 B: the MSP430F149 has 60 KB of flash and 2 KB of RAM, so tables go to flash).
/// Why 16 bits and not 32: frames are at most 257 bytes, where CRC-16/CCITT detects every error
/// of up to 3 bits and every burst of up to 16 (Hamming distance 4 below 4096 bits), and the
/// MSP430 has no 32-bit shift instruction; docs/PROTOCOL.md.
#pragma once

#include <stddef.h>
#include <stdint.h>

namespace gyroflip::protocol {

inline constexpr uint16_t crc16_init = 0xFFFFu;

namespace detail {
struct crc16_table {
  uint16_t v[256];
};
constexpr crc16_table make_crc16_table() {
  crc16_table t{};
  for (unsigned i = 0; i < 256u; ++i) {
    uint16_t c = static_cast<uint16_t>(i << 8);
    for (int b = 0; b < 8; ++b)
      c = static_cast<uint16_t>((c & 0x8000u) != 0 ? (unsigned{c} << 1u) ^ 0x1021u
                                                   : unsigned{c} << 1u);
    t.v[i] = c;
  }
  return t;
}
inline constexpr crc16_table crc16_lut = make_crc16_table();
}  // namespace detail

/// Adds one byte to a running CRC.
[[nodiscard]] constexpr uint16_t crc16_byte(uint16_t crc, uint8_t b) {
  return static_cast<uint16_t>((crc << 8) ^ detail::crc16_lut.v[((crc >> 8) ^ b) & 0xFFu]);
}

/// CRC of `n` bytes at `p`, continuing from `crc`.
[[nodiscard]] constexpr uint16_t crc16(const uint8_t* p, size_t n, uint16_t crc = crc16_init) {
  for (size_t i = 0; i < n; ++i) crc = crc16_byte(crc, p[i]);
  return crc;
}

namespace detail {
inline constexpr uint8_t crc16_check_input[9] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
}
static_assert(crc16(detail::crc16_check_input, 9) == 0x29B1u, "CRC-16/CCITT-FALSE check value");

}  // namespace gyroflip::protocol
