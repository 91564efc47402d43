/// \file
/// \brief AD7739 conversion time and code format: the facts both the firmware and the host
/// simulator rely on. Integer only (the firmware has no floating point at run time).
///
/// Conversion time in master-clock cycles (MCLK nominally 6.144 MHz):
///   chop on:  128 FW + 249      chop off:  64 FW + 206
/// Source: the AD7739 data sheet's channel conversion-time register description gives the
/// conversion time as (FW x 128 + 249) / f_MCLK with CHOP = 1 and (FW x 64 + 206) / f_MCLK with
/// CHOP = 0. Checked against the family's published timing (AD7732 data sheet Rev. A, p. 28,
/// "Multiplexer, Conversion, and Data Output Timing"): chop on is a settling of 43 or 44 MCLK,
/// a sampling time, a second settling of 42 MCLK, the sampling again and a scaling of 163 MCLK,
/// i.e. 2 x sampling + 248..249; chop off is 43..44 + sampling + 163 = sampling + 206..207. Both
/// agree with a sampling time of 64 FW cycles, and with the AD7739's front page (FW = 3 without
/// chop: 64.8 us, "up to 15 kHz"; FW = 10 with chop: 249 us, "250 us, 4 kHz channel
/// switching"). The 1-cycle spread of the settling (43 or 44) is below a tick of any timer here.
/// FW = 94 with chop: 12 281 cycles = 1.9989 ms (500.3 Hz), the paper's "2 ms" (docs/HARDWARE.md).
///
/// Codes: offset binary, 0 at -full scale, 2^23 at 0 V, 2^24 - 1 at +full scale (bipolar
/// ranges); the firmware and the protocol carry signed codes, code - 2^23.
#pragma once

#include <stdint.h>

namespace gyroflip::ad7739 {

inline constexpr uint32_t mclk_hz_nominal = 6144000;
inline constexpr uint8_t fw_min = 2;
inline constexpr uint8_t fw_max = 127;
inline constexpr int32_t code_zero = int32_t{1} << 23;
inline constexpr int32_t code_max = (int32_t{1} << 24) - 1;

/// Master-clock cycles of one conversion (formula above).
[[nodiscard]] constexpr uint32_t conversion_mclk(bool chop, uint8_t fw) {
  return chop ? 128u * fw + 249u : 64u * fw + 206u;
}

/// Signed code (code - 2^23) of a raw 24-bit offset-binary code.
[[nodiscard]] constexpr int32_t to_signed(uint32_t raw24) {
  return static_cast<int32_t>(raw24 & 0xFFFFFFu) - code_zero;
}

/// Full scale of a range in microvolts (the span of a bipolar range is twice this).
[[nodiscard]] constexpr uint32_t full_scale_uv(uint8_t range_code) {
  switch (range_code & 0x07u) {
    case 0:
    case 1:
      return 1250000u;
    case 2:
    case 3:
      return 625000u;
    default:
      return 2500000u;
  }
}

static_assert(conversion_mclk(true, 94) == 12281u);
static_assert(conversion_mclk(false, 3) == 398u);
static_assert(to_signed(0x800000u) == 0 && to_signed(0) == -8388608 &&
              to_signed(0xFFFFFFu) == 8388607);

}  // namespace gyroflip::ad7739
