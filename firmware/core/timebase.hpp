/// \file
/// \brief Time conversions of the firmware core: milliseconds and ADC master-clock cycles to
/// ticks of the device's timer. Integer only, and in 32 bits wherever the operands allow: a
/// 64-bit division in software costs the MSP430F149 thousands of cycles, and these run at
/// CONFIGURE, inside one main-loop pass. Each equals the exact 64-bit formula (the MSP430
/// instruction simulator checks them bit for bit against the host, selftest.hpp).
#pragma once

#include <stdint.h>

namespace gyroflip::fw {

/// `ms` milliseconds (below 65 536) in ticks of a `tick_hz` timer (below 65.5 MHz), rounded up
/// (a wait is never shorter): ceil(ms tick_hz / 1000) = ms q + ceil(ms r / 1000) with
/// tick_hz = 1000 q + r, every product below 2^32.
[[nodiscard]] constexpr uint32_t ms_to_ticks(uint32_t ms, uint32_t tick_hz) {
  const uint32_t q = tick_hz / 1000;
  const uint32_t r = tick_hz % 1000;
  return ms * q + (ms * r + 999) / 1000;
}

/// `cycles` of an `mclk_hz` clock in ticks of a `tick_hz` timer, rounded up, at least 1: in 32
/// bits when cycles x tick_hz fits (the MSP430F149's 32 768 Hz ticks: every AD7739 conversion),
/// else in 64.
[[nodiscard]] constexpr uint32_t mclk_to_ticks(uint32_t cycles, uint32_t tick_hz,
                                               uint32_t mclk_hz) {
  uint32_t t = 0;
  if (cycles == 0 || tick_hz <= 0xFFFFFFFFu / cycles) {
    const uint32_t p = cycles * tick_hz;
    t = p / mclk_hz + (p % mclk_hz != 0 ? 1u : 0u);
  } else {
    t = static_cast<uint32_t>((uint64_t{cycles} * tick_hz + mclk_hz - 1) / mclk_hz);
  }
  return t == 0 ? 1 : t;
}

static_assert(ms_to_ticks(1000, 32768) == 32768 && ms_to_ticks(1, 32768) == 33);
static_assert(ms_to_ticks(65535, 1000000) == 65535000u && ms_to_ticks(7, 1000000) == 7000);
static_assert(mclk_to_ticks(12281, 32768, 6144000) == 66 && mclk_to_ticks(1, 32768, 6144000) == 1);
static_assert(mclk_to_ticks(16505, 1000000, 6144000) == 2687);

}  // namespace gyroflip::fw
