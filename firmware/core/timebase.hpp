/// \file
/// \brief Time conversions of the firmware core: milliseconds and ADC master-clock cycles to
/// ticks of the device's timer. Integer only; 64-bit intermediates (on the MSP430 these call
/// the runtime's 64-bit multiply and divide, checked on the instruction simulator). The device
/// converts once per configuration, never per poll (a software 64-bit division costs the
/// MSP430F149 thousands of cycles).
#pragma once

#include <stdint.h>

namespace gyroflip::fw {

/// `ms` milliseconds in ticks of a `tick_hz` timer, rounded up (a wait is never shorter).
[[nodiscard]] constexpr uint32_t ms_to_ticks(uint32_t ms, uint32_t tick_hz) {
  return static_cast<uint32_t>((uint64_t{ms} * tick_hz + 999) / 1000);
}

/// `cycles` of an `mclk_hz` clock in ticks of a `tick_hz` timer, rounded up, at least 1.
[[nodiscard]] constexpr uint32_t mclk_to_ticks(uint32_t cycles, uint32_t tick_hz,
                                               uint32_t mclk_hz) {
  const uint64_t t = (uint64_t{cycles} * tick_hz + mclk_hz - 1) / mclk_hz;
  return t == 0 ? 1 : static_cast<uint32_t>(t);
}

static_assert(ms_to_ticks(1000, 32768) == 32768 && ms_to_ticks(1, 32768) == 33);
static_assert(mclk_to_ticks(12281, 32768, 6144000) == 66 && mclk_to_ticks(1, 32768, 6144000) == 1);

}  // namespace gyroflip::fw
