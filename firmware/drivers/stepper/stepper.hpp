/// \file
/// \brief Unipolar stepper motors on one 8-bit port (paper section 3: two motors from the two
/// nibbles of one port through ULN2003-class drivers): the full-step sequence, a position
/// counter per motor, and a trapezoidal acceleration ramp in integer arithmetic.
#pragma once

#include <stdint.h>

namespace gyroflip::stepper {

/// Full-step, two-phase-on sequence of a unipolar motor: coils A, B, A', B' on bits 0..3 of the
/// nibble; each step moves one place (forward = increasing index). Two coils are always on,
/// which gives the full-step holding torque (one-phase-on would give ~1/sqrt(2) of it).
inline constexpr uint8_t full_step[4] = {0x3, 0x6, 0xC, 0x9};

struct motor {
  int32_t position = 0;  ///< steps from the start (or home), counted by the driver
  uint8_t phase = 0;     ///< index into full_step
  bool energised = false;
  /// One step in direction `dir` (+1 or -1).
  void step(int8_t dir) {
    phase = static_cast<uint8_t>((phase + (dir > 0 ? 1u : 3u)) & 3u);
    position += dir;
    energised = true;
  }
  [[nodiscard]] uint8_t nibble() const { return energised ? full_step[phase] : 0; }
};

/// The port byte for two motors: motor 0 on the low nibble, motor 1 on the high one, so a step
/// of one never changes the other's coils.
[[nodiscard]] inline uint8_t port_byte(const motor& low, const motor& high) {
  return static_cast<uint8_t>(low.nibble() | (high.nibble() << 4));
}

/// A trapezoidal speed profile: from `start_sps` up at `accel_sps2` to at most `top_sps`, and
/// down again symmetrically. Rates in steps/s, accel in steps/s^2.
struct ramp {
  uint16_t start_sps = 100;
  uint16_t top_sps = 400;
  uint16_t accel_sps2 = 2000;
};

/// The rate (steps/s) of step k (0-based) of an n-step move: v = sqrt(v0^2 + 2 a j) with j the
/// number of steps already taken from the nearer end of the move (constant acceleration from v0
/// over j steps, v^2 = v0^2 + 2 a s), limited to the top rate.
[[nodiscard]] uint16_t step_rate(const ramp& r, uint32_t k, uint32_t n);

/// Ticks from step k to step k+1 at `tick_hz` (rounded to nearest, at least 1).
[[nodiscard]] uint32_t step_interval(const ramp& r, uint32_t k, uint32_t n, uint32_t tick_hz);

/// What the motor that does not flip does (protocol other_motor values).
enum class follower : uint8_t { off = 0, hold = 1, same = 2, opposite = 3 };

/// A move of the flipping motor by `steps` (sign = direction), the other following its rule,
/// timed by the ramp. Poll it with the tick counter; it writes the port through `out`.
class mover {
 public:
  /// A move of `steps`, its first step due at `first_ticks`.
  void begin(int32_t steps, uint32_t first_ticks) {
    total_ = steps < 0 ? static_cast<uint32_t>(-steps) : static_cast<uint32_t>(steps);
    dir_ = steps < 0 ? -1 : 1;
    done_steps_ = 0;
    next_ = first_ticks;
  }
  /// Takes the next step if it is due at `now` (at most one: write the port after each call);
  /// true while the move is not finished.
  bool poll(uint32_t now, const ramp& r, uint32_t tick_hz, motor& flip, motor& other,
            follower rule);
  [[nodiscard]] bool busy() const { return done_steps_ < total_; }
  /// When the next step is due (ticks).
  [[nodiscard]] uint32_t next_due() const { return next_; }
  [[nodiscard]] uint32_t steps_done() const { return done_steps_; }

 private:
  uint32_t total_ = 0;
  uint32_t done_steps_ = 0;
  int8_t dir_ = 1;
  uint32_t next_ = 0;
};

}  // namespace gyroflip::stepper
