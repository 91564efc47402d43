/// \file
/// \brief Consistent Overhead Byte Stuffing (Cheshire & Baker, "Consistent Overhead Byte
/// Stuffing", IEEE/ACM Trans. Networking 7(2), 1999): a frame without any 0x00 byte, so that 0x00
/// delimits frames and a receiver resynchronises at the next 0x00 after any corruption. Overhead:
/// at most 1 byte per 254, plus the delimiter the caller appends. No allocation.
#pragma once

#include <stddef.h>
#include <stdint.h>

namespace gyroflip::protocol {

/// Largest encoded size of `n` bytes (without the delimiter).
[[nodiscard]] constexpr size_t cobs_max_encoded(size_t n) {
  return n + n / 254u + 1u;
}

/// Encodes `n` bytes of `src` into `dst` (capacity `cap`); returns the encoded length, or 0 when
/// `cap` is too small. The output holds no 0x00. In place: `src` may lie inside `dst` at an
/// offset of at least `cobs_max_encoded(n) - n` bytes (every write then trails the reads), so a
/// device needs one frame buffer, not two.
[[nodiscard]] size_t cobs_encode(const uint8_t* src, size_t n, uint8_t* dst, size_t cap);

/// Decodes `n` bytes of `src` (no delimiter) into `dst` (capacity `cap`); returns the decoded
/// length, or -1 when the input is not valid COBS (a 0x00 byte, a code past the end) or `cap`
/// is too small. `dst` may equal `src` (decoding in place).
[[nodiscard]] long cobs_decode(const uint8_t* src, size_t n, uint8_t* dst, size_t cap);

}  // namespace gyroflip::protocol
