/// \file
/// \brief Little-endian field writer and reader over a fixed buffer (no allocation): the bytes of
/// every message field, whatever the machine's byte order or int width (the MSP430's int is 16
/// bits). Shifts are by the constant 8 only: the MSP430 has no barrel shifter, and a variable
/// shift of a 32- or 64-bit value would be a runtime-library call. A write or read past the end
/// sets `ok = false` and does nothing.
#pragma once

#include <stddef.h>
#include <stdint.h>

namespace gyroflip::protocol {

struct writer {
  uint8_t* p;
  size_t cap;
  size_t n = 0;
  bool ok = true;

  /// Reserves `count` bytes; null (and ok = false) when they do not fit.
  uint8_t* take(size_t count) {
    if (!ok || cap - n < count) {
      ok = false;
      return nullptr;
    }
    uint8_t* at = p + n;
    n += count;
    return at;
  }
  void u8(uint8_t v) {
    if (uint8_t* at = take(1)) at[0] = v;
  }
  void u16(uint16_t v) {
    if (uint8_t* at = take(2)) {
      at[0] = static_cast<uint8_t>(v);
      at[1] = static_cast<uint8_t>(v >> 8);
    }
  }
  void u32(uint32_t v) { le(v, 4); }
  void i16(int16_t v) { u16(static_cast<uint16_t>(v)); }
  void i32(int32_t v) { le(static_cast<uint32_t>(v), 4); }
  /// A 24-bit two's-complement value (a signed AD7739 code): the low 3 bytes.
  void i24(int32_t v) { le(static_cast<uint32_t>(v), 3); }
  /// A 48-bit two's-complement value (a sum of up to 65 535 codes): the low 6 bytes.
  void i48(int64_t v) {
    const auto u = static_cast<uint64_t>(v);
    le(static_cast<uint32_t>(u), 4);
    le(static_cast<uint32_t>(u >> 32), 2);
  }

 private:
  void le(uint32_t v, unsigned count) {
    if (uint8_t* at = take(count)) {
      for (unsigned i = 0; i < count; ++i, v >>= 8) at[i] = static_cast<uint8_t>(v);
    }
  }
};

struct reader {
  const uint8_t* p;
  size_t len;
  size_t n = 0;
  bool ok = true;

  /// The next `count` bytes; null (and ok = false) past the end.
  const uint8_t* take(size_t count) {
    if (!ok || len - n < count) {
      ok = false;
      return nullptr;
    }
    const uint8_t* at = p + n;
    n += count;
    return at;
  }
  uint8_t u8() {
    const uint8_t* at = take(1);
    return at != nullptr ? at[0] : 0;
  }
  uint16_t u16() {
    const uint8_t* at = take(2);
    return at != nullptr ? static_cast<uint16_t>(at[0] | (at[1] << 8)) : 0;
  }
  uint32_t u32() { return le(4); }
  int16_t i16() { return static_cast<int16_t>(u16()); }
  int32_t i32() { return static_cast<int32_t>(le(4)); }
  /// Sign-extends the 24-bit field.
  int32_t i24() {
    const uint32_t v = le(3);
    return static_cast<int32_t>((v ^ 0x800000u) - 0x800000u);
  }
  /// Sign-extends the 48-bit field.
  int64_t i48() {
    const uint32_t lo = le(4);
    const uint32_t hi = le(2);
    const uint64_t v = (static_cast<uint64_t>(hi) << 32) | lo;
    constexpr uint64_t sign = uint64_t{1} << 47;
    return static_cast<int64_t>((v ^ sign) - sign);
  }
  /// True when every byte was read and no read failed (a frame with trailing bytes is malformed).
  [[nodiscard]] bool done() const { return ok && n == len; }

 private:
  uint32_t le(unsigned count) {
    const uint8_t* at = take(count);
    uint32_t v = 0;
    if (at != nullptr) {
      for (unsigned i = count; i-- > 0;) v = (v << 8) | at[i];
    }
    return v;
  }
};

}  // namespace gyroflip::protocol
