/// \file
/// \brief A model of two unipolar steppers on one 8-bit port: each nibble's full-step pattern
/// is decoded into a position; a change by two places at once, or a nibble that is neither off
/// nor a full-step pattern, is counted as a fault (a real motor would not follow it).
/// Freestanding: the host port and the Cortex-M3 image both use it.
#pragma once

#include <stdint.h>

#include "firmware/drivers/stepper/stepper.hpp"

namespace gyroflip::fw::model {

struct stepper_port_model {
  uint8_t port = 0;              ///< the last byte written
  int32_t position[2] = {0, 0};  ///< decoded position of the low and high nibble's motor
  uint32_t writes = 0;
  uint32_t bad_transitions = 0;

  /// A motor whose coils go off stays at the detent of its last phase (no load turns it); the
  /// next pattern it is given moves it from there.
  void write(uint8_t v) {
    for (int m = 0; m < 2; ++m) {
      const int after = phase_of(nibble(v, m));
      if (nibble(v, m) != 0 && after < 0) ++bad_transitions;
      if (after < 0) continue;  // off (the rotor stays), or not a full step
      const int before = last_phase_[m];
      last_phase_[m] = after;
      if (before < 0 || before == after) continue;  // first energised, or unchanged
      const int d = (after - before + 4) % 4;
      if (d == 1) ++position[m];
      if (d == 3) --position[m];
      if (d == 2) ++bad_transitions;
    }
    port = v;
    ++writes;
  }
  /// Motor m's coils are energised.
  [[nodiscard]] bool energised(int m) const { return nibble(port, m) != 0; }

 private:
  static uint8_t nibble(uint8_t v, int m) {
    return static_cast<uint8_t>((unsigned{v} >> (m == 0 ? 0u : 4u)) & 0xFu);
  }
  /// Index of a nibble in the full-step sequence, or -1 (coils off or not a full step).
  static int phase_of(uint8_t nib) {
    for (int i = 0; i < 4; ++i)
      if (stepper::full_step[i] == nib) return i;
    return -1;
  }
  int last_phase_[2] = {-1, -1};
};

}  // namespace gyroflip::fw::model
