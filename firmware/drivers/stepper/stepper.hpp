/// \file
/// \brief Unipolar stepper motors on one 8-bit port (paper section 3: two motors from the two
/// nibbles of one port through ULN2003-class drivers): the full-step sequence, a position
/// counter per motor, and a trapezoidal acceleration ramp in integer arithmetic, with the step
/// instants kept by a timer compare (docs/FIRMWARE.md, "Steps on a timer").
#pragma once

#include <stdint.h>

#include "firmware/util/intmath.hpp"
#include "firmware/util/shared.hpp"

namespace gyroflip::stepper {

using fw::share;
using fw::shared;

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
/// over j steps, v^2 = v0^2 + 2 a s), limited to the top rate. The reference formula (64-bit);
/// the device uses ramp_plan, which gives the same intervals in 32 bits.
[[nodiscard]] uint16_t step_rate(const ramp& r, uint32_t k, uint32_t n);

/// Ticks from step k to step k+1 at `tick_hz` (rounded to nearest, at least 1).
[[nodiscard]] uint32_t step_interval(const ramp& r, uint32_t k, uint32_t n, uint32_t tick_hz);

/// floor(sqrt(v)) of a 32-bit value: 16 rounds of 32-bit adds and shifts, no multiplication or
/// division (fw::isqrt_bits).
[[nodiscard]] constexpr uint32_t isqrt32(uint32_t v) {
  return fw::isqrt_bits<uint32_t>(v);
}
static_assert(isqrt32(0) == 0 && isqrt32(24) == 4 && isqrt32(25) == 5 &&
              isqrt32(0xFFFFFFFFu) == 0xFFFFu);

/// A ramp prepared once per configuration (CONFIGURE), so that a step's interval costs one
/// 32-bit square root and one division (about 1 000 MCLK cycles on the MSP430F149 instead of
/// the 64-bit formula's ~15 000): the start rate squared, twice the acceleration, and the number
/// of steps below the top rate, j_top = ceil((top^2 - v0^2) / 2a); from there on the interval
/// is the top rate's. interval() equals step_interval() for every step of every move
/// (tests/firmware/test_drivers.cpp, and on the MSP430 tests/firmware/test_msp430_sim.cpp).
struct ramp_plan {
  uint32_t v0_sq = 1;
  uint32_t two_a = 2;
  uint32_t tick_hz = 1;
  uint16_t ramp_steps = 0;  ///< j_top: steps j with v0^2 + 2 a j < top^2
  uint16_t top_sps = 1;
  uint32_t cruise_ticks = 1;
};
/// The plan of ramp `r` at `tick_hz` (rates >= 1; a top below the start rate is the start rate).
[[nodiscard]] ramp_plan make_plan(const ramp& r, uint32_t tick_hz);
/// Ticks from step k to step k+1 of an n-step move (k < n): step_interval(r, k, n, tick_hz).
[[nodiscard]] uint32_t interval(const ramp_plan& p, uint32_t k, uint32_t n);

/// What the motor that does not flip does (protocol other_motor values).
enum class follower : uint8_t { off = 0, hold = 1, same = 2, opposite = 3 };

/// A move of the flipping motor by `steps` (sign = direction), the other following its rule,
/// its steps timed by the ramp. Two sides share it:
///  - the producer (the main loop, refill()) computes the intervals of the steps ahead into a
///    small queue;
///  - the consumer (a timer-compare interrupt, or the main loop on a port without one,
///    take_step()) takes each step at its instant and schedules the next from the queue.
/// Each side writes only its own indices (8- and 16-bit, single accesses on the MSP430, read
/// through fw::shared()): no lock. The cruise (the steps at the top rate) needs no queue: its
/// interval is a constant the consumer takes itself, so only the ramps' steps are computed and
/// queued, and a move cannot run dry at its top rate.
/// When the consumer finds the queue empty (the main loop fell behind), the move pauses and the
/// main loop restarts the ramp from standstill for the steps left (rebase()): a motor never gets
/// a burst of late steps or a top-rate step after a pause.
class mover {
 public:
  /// Intervals computed ahead of the steps: at the F149's top rate (limits.hpp, 1 200 steps/s)
  /// the main loop may be 6.7 ms late before a move pauses (4 ms at 2 000 steps/s).
  static constexpr uint8_t queue_len = 8;

  /// A move of `steps`, its first step due at `first_ticks`; the first `ahead` intervals are
  /// computed now (the start rate's steps are the slowest: refill() keeps ahead of them).
  void begin(int32_t steps, uint32_t first_ticks, const ramp_plan& p, uint8_t ahead = queue_len);
  /// The first step's instant, set after begin() (whose interval computations take time).
  void retime(uint32_t first_ticks) { next_ = first_ticks; }
  /// Main loop: computes intervals ahead while the queue has room (at most `max_new`) and holds
  /// less time than a full queue at the top rate (queue_len cruise intervals).
  void refill(const ramp_plan& p, uint8_t max_new = queue_len);
  /// The step due at `now` (the consumer's side): moves the motors, and returns true with
  /// `*next_due` the instant of the following step when it is queued; false when the move is
  /// done or the queue ran dry (paused()). A step taken a whole interval or more after its
  /// instant times the next one from `now` (no burst of catch-up steps).
  bool take_step(motor& flip, motor& other, follower rule, uint32_t now, uint32_t* next_due);
  /// The consumer found no interval queued for the next step: the move waits for rebase().
  [[nodiscard]] bool paused() const { return shared(paused_) && busy(); }
  /// Main loop: restarts the ramp from standstill for the steps left, the next due at `now`.
  void rebase(uint32_t now, const ramp_plan& p);

  [[nodiscard]] bool busy() const { return shared(done_) < total_; }
  /// When the next step is due (ticks).
  [[nodiscard]] uint32_t next_due() const { return next_; }
  [[nodiscard]] uint16_t steps_done() const { return shared(done_); }
  [[nodiscard]] uint16_t rebases() const { return rebases_; }

 private:
  [[nodiscard]] bool cruising(uint16_t k) const;
  /// interval(p, j-th step of a ramp): the root of v0^2 + 2 a j kept from the last call (j moves
  /// by one between calls: adds and compares, no square root), then one division.
  [[nodiscard]] uint32_t ramp_ticks(const ramp_plan& p, uint16_t j);
  /// ticks_at(p.tick_hz, v): from the last interval (t_) with a product and a few adds when the
  /// rate moved little since (a running root's step), else one division.
  [[nodiscard]] uint32_t ticks_near(const ramp_plan& p, uint16_t v);
  /// The running root's step to j in 16-bit arithmetic (the F149's ramps); false where it would
  /// not fit (then the 32-bit code).
  [[nodiscard]] bool root_step16(const ramp_plan& p, uint16_t j);
  /// The root at j from scratch (isqrt32).
  [[gnu::noinline]] void root_at(const ramp_plan& p, uint16_t j);
  /// ticks_at(p.tick_hz, root_) from t_ (the interval at `v_old`) in 16-bit arithmetic; 0 where
  /// it would not fit (then ticks_near).
  [[nodiscard]] uint16_t ticks_step16(const ramp_plan& p, uint16_t v_old);
  void restart_root(const ramp_plan& p);

  uint16_t total_ = 0;
  uint16_t ramp_steps_ = 0;  // the plan's j_top and top-rate interval (copied at begin())
  uint16_t cruise_ticks_ = 1;
  uint16_t done_ = 0;      // consumer
  uint16_t seg_base_ = 0;  // the step where the current ramp began (producer)
  uint16_t queued_ = 0;    // steps whose interval to the next is queued (producer)
  uint16_t rebases_ = 0;
  int8_t dir_ = 1;
  uint8_t head_ = 0;  // consumer
  uint8_t tail_ = 0;  // producer
  bool paused_ = false;
  uint32_t next_ = 0;
  uint16_t queue_[queue_len] = {};
  // The producer's running root: root_^2 + rest_ = v0^2 + 2 a root_j_, 0 <= rest_ <= 2 root_.
  uint16_t root_j_ = 0;
  uint16_t root_ = 1;
  uint16_t rest_ = 0;
  uint16_t t_ = 0;  // ticks_at(tick_hz, root_) (0: not known, or above 16 bits)
};

}  // namespace gyroflip::stepper
