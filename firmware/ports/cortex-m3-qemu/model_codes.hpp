/// \file
/// \brief The codes of the Cortex-M3 image's in-image AD7739 model: a deterministic function
/// of the conversion index and the table's position, so a host test can recompute every DWELL
/// the image sends. A model, not a gyro: base + (A: +rate, B: -rate) + a hashed noise term.
#pragma once

#include <stdint.h>

namespace gyroflip::fw::qemu {

inline constexpr int32_t model_base = 52000;
inline constexpr int32_t model_rate = 1700;
inline constexpr int32_t model_noise = 900;
inline constexpr int32_t model_temp = -123456;

[[nodiscard]] constexpr int32_t model_gyro_code(uint32_t index, bool at_b) {
  uint32_t x = index * 747796405u + 2891336453u;
  x ^= x >> 15;
  x *= 277803737u;
  x ^= x >> 16;
  const int32_t noise = static_cast<int32_t>(x % (2u * model_noise + 1u)) - model_noise;
  return model_base + (at_b ? -model_rate : model_rate) + noise;
}

}  // namespace gyroflip::fw::qemu
