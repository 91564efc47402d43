/// \file
/// \brief The device's non-volatile records (the MSP430F149's information flash,
/// docs/HARDWARE.md "Information flash"): the board's serial, written once by the lab that
/// builds the board (firmware/ports/msp430f149/board_record.py), and the dN in force, written by
/// the device. Ten bytes each:
///   'G' 'F' kind version value(u32, LE) crc(u16, LE)
/// the CRC-16/CCITT-FALSE of the first eight bytes. Erased flash (0xFF) or a torn write fails
/// the magic or the CRC, and the record is then absent (the serial 0, dN 0).
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "firmware/protocol/crc16.hpp"

namespace gyroflip::fw::nv {

inline constexpr size_t record_bytes = 10;
inline constexpr uint8_t kind_board_serial = 1;
inline constexpr uint8_t kind_delta_n = 2;
inline constexpr uint8_t version = 1;

/// Record of `kind` holding `value`, into out[0..record_bytes).
constexpr void encode(uint8_t kind, uint32_t value, uint8_t* out) {
  out[0] = 'G';
  out[1] = 'F';
  out[2] = kind;
  out[3] = version;
  for (int i = 0; i < 4; ++i) out[4 + i] = static_cast<uint8_t>(value >> (8 * i));
  const uint16_t crc = protocol::crc16(out, 8);
  out[8] = static_cast<uint8_t>(crc & 0xFFu);
  out[9] = static_cast<uint8_t>(crc >> 8);
}

/// The value of a record of `kind`; false when `in` is not one (magic, kind, version or CRC).
constexpr bool decode(const uint8_t* in, uint8_t kind, uint32_t* value) {
  if (in[0] != 'G' || in[1] != 'F' || in[2] != kind || in[3] != version) return false;
  const uint16_t crc = protocol::crc16(in, 8);
  if (in[8] != (crc & 0xFFu) || in[9] != (crc >> 8)) return false;
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | in[4 + i];
  *value = v;
  return true;
}

}  // namespace gyroflip::fw::nv
