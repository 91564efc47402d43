/// \file
/// \brief Integer helpers of the firmware: square roots and rounded division. Freestanding, no
/// floating point (the MSP430F149 has no FPU; its runtime would emulate it in ~1 KB of code).
#pragma once

#include <stdint.h>

namespace gyroflip::fw {

/// floor(sqrt(v)) of an unsigned value of any width, the bit-by-bit method (Warren, Hacker's
/// Delight, 2nd ed., Fig. 11-4): no multiplication or division, exact for every input; one round
/// per two bits of U.
template <class U>
[[nodiscard]] constexpr U isqrt_bits(U v) {
  U root = 0;
  U bit = U{1} << (8 * sizeof(U) - 2);
  while (bit > v) bit >>= 2;
  while (bit != 0) {
    if (v >= root + bit) {
      v -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  return root;
}
/// floor(sqrt(v)) of a 64-bit value (isqrt_bits).
[[nodiscard]] constexpr uint64_t isqrt(uint64_t v) {
  return isqrt_bits<uint64_t>(v);
}

/// num / den rounded to nearest, halves away from zero (den > 0): the rounding of
/// std::llround(double(num) / den) without the double.
[[nodiscard]] constexpr int64_t div_round(int64_t num, uint64_t den) {
  const uint64_t mag =
      num < 0 ? uint64_t{0} - static_cast<uint64_t>(num) : static_cast<uint64_t>(num);
  const uint64_t q = (mag + den / 2) / den;
  return num < 0 ? -static_cast<int64_t>(q) : static_cast<int64_t>(q);
}

/// v clamped to the int32_t range.
[[nodiscard]] constexpr int32_t saturate(int64_t v) {
  constexpr int64_t lo = -2147483647 - 1;
  constexpr int64_t hi = 2147483647;
  return static_cast<int32_t>(v < lo ? lo : (v > hi ? hi : v));
}

static_assert(isqrt(0) == 0 && isqrt(15) == 3 && isqrt(16) == 4 &&
              isqrt(~uint64_t{0}) == 0xFFFFFFFFu);
static_assert(div_round(5, 2) == 3 && div_round(-5, 2) == -3 && div_round(4, 3) == 1 &&
              div_round(-4, 3) == -1);

}  // namespace gyroflip::fw
