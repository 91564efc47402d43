// The AD7739 driver against the register-level model, and the stepper driver (issue 8).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "firmware/drivers/ad7739/ad7739.hpp"
#include "firmware/drivers/stepper/stepper.hpp"
#include "firmware/ports/host/board.hpp"

namespace {

using namespace gyroflip;
using fw::model::host_board;
namespace a = gyroflip::ad7739;

struct code_list {
  std::vector<int32_t> codes;
  static int32_t call(void* ctx, uint8_t, uint32_t index) {
    const auto& c = *static_cast<const code_list*>(ctx);
    return c.codes[index % c.codes.size()];
  }
};

// Waits for RDY on the virtual clock; false after `limit` ticks.
bool wait_rdy(host_board& b, const a::driver& d, uint32_t limit) {
  for (uint32_t i = 0; i < limit; ++i, ++b.now)
    if (d.ready()) return true;
  return false;
}

TEST(Ad7739Driver, WritesTheRegistersTheDataSheetRequiresInOrder) {
  code_list src{{0}};
  host_board b(&code_list::call, &src);
  a::driver d(b.hw());
  ASSERT_EQ(d.reset(), fw::status::ok);
  EXPECT_EQ(b.adc.resets(), 1u);  // 32 ones reset the part
  uint8_t rev = 0;
  ASSERT_EQ(d.read_revision(&rev), fw::status::ok);
  EXPECT_EQ(rev, fw::model::ad7739_model::revision);
  b.adc.clear_log();
  ASSERT_EQ(d.setup_channel(1, a::range_bipolar_2v5), fw::status::ok);
  ASSERT_EQ(d.set_conversion_time(1, true, 94), fw::status::ok);
  ASSERT_EQ(d.self_calibrate(1, 1000), fw::status::ok);
  ASSERT_EQ(d.start_single(1), fw::status::ok);
  // Channel setup (0x28 + ch): differential, +-2.5 V; conversion time (0x30 + ch): CHOP | FW;
  // mode (0x38 + ch): ADC zero-scale self-cal, then full-scale, then a single conversion, all
  // 24-bit, the conversion in dump mode (data sheet Rev. A register descriptions; regs.hpp).
  const std::vector<std::pair<uint8_t, uint32_t>> want = {
      {0x29, 0x24}, {0x31, 0x80 | 94}, {0x39, 0x82}, {0x39, 0xA2}, {0x39, 0x4A}};
  ASSERT_EQ(b.adc.log_size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(b.adc.log()[i].addr, want[i].first) << i;
    EXPECT_EQ(b.adc.log()[i].value, want[i].second) << i;
  }
  // Out-of-range arguments never reach the bus.
  EXPECT_EQ(d.set_conversion_time(0, true, 1), fw::status::bad_arg);
  EXPECT_EQ(d.set_conversion_time(0, true, 128), fw::status::bad_arg);
  EXPECT_EQ(d.setup_channel(8, 4), fw::status::bad_arg);
  EXPECT_EQ(b.adc.log_size(), want.size());
}

TEST(Ad7739Driver, CodesReadBackBitExact) {
  code_list src{{0, -1, 1, -8388608, 8388607, 123456, -654321, 0x2AAAAA, -0x155555}};
  host_board b(&code_list::call, &src);
  a::driver d(b.hw());
  ASSERT_EQ(d.set_conversion_time(0, false, 3), fw::status::ok);  // fastest: 398 MCLK
  for (size_t i = 0; i < src.codes.size(); ++i) {
    ASSERT_EQ(d.start_single(0), fw::status::ok);
    ASSERT_TRUE(wait_rdy(b, d, 100));
    int32_t code = 7;
    uint8_t st = 0;
    ASSERT_EQ(d.read_result(0, &code, &st), fw::status::ok);
    EXPECT_EQ(code, src.codes[i]) << i;
    // Dump mode: the channel status first: channel 0, its RDY bit, the sign of the input.
    EXPECT_EQ(st >> a::chst_channel_shift, 0);
    EXPECT_NE(st & a::chst_rdy, 0);
    EXPECT_EQ((st & a::chst_sign) != 0, src.codes[i] < 0) << i;
    EXPECT_FALSE(d.ready());  // reading the data register clears RDY
  }
}

// Data sheet Rev. A: /RDY goes high only in the scaling time at the end of a conversion, so a
// result nobody read (here: the self-calibration's) keeps it low through the mode write that
// starts the next conversion. A driver that trusts the pin sums that stale result; the channel
// status (RDY bit, channel) and the conversion time tell it apart.
TEST(Ad7739Driver, RdyStaysLowFromAnUnreadResultUntilTheScalingTime) {
  code_list src{{4242}};
  host_board b(&code_list::call, &src);
  a::driver d(b.hw());
  ASSERT_EQ(d.set_conversion_time(0, true, 94), fw::status::ok);
  ASSERT_EQ(d.self_calibrate(0, 1000), fw::status::ok);
  ASSERT_EQ(d.start_single(0), fw::status::ok);
  EXPECT_TRUE(d.ready()) << "a mode write must not clear a pending ready at once";
  const uint32_t t0 = b.now;
  // Before the scaling time it stays low; in it, high; then low with the new result.
  b.now = t0 + 30;
  EXPECT_TRUE(d.ready());
  bool went_high = false;
  uint32_t low_at = 0;
  for (uint32_t t = t0 + 30; t < t0 + 200; ++t) {
    b.now = t;
    if (!d.ready()) went_high = true;
    if (went_high && d.ready()) {
      low_at = t;
      break;
    }
  }
  EXPECT_TRUE(went_high);
  EXPECT_EQ(low_at - t0, 66u);  // the conversion time: 12 281 MCLK at 32 768 Hz ticks
  int32_t code = 0;
  uint8_t st = 0;
  ASSERT_EQ(d.read_result(0, &code, &st), fw::status::ok);
  EXPECT_EQ(code, 4242);
}

TEST(Ad7739Driver, RdyComesAfterTheConversionTime) {
  code_list src{{5}};
  host_board b(&code_list::call, &src);
  a::driver d(b.hw());
  for (const bool chop : {true, false}) {
    for (const uint8_t fw : {uint8_t{2}, uint8_t{94}, uint8_t{127}}) {
      ASSERT_EQ(d.set_conversion_time(0, chop, fw), fw::status::ok);
      ASSERT_EQ(d.start_single(0), fw::status::ok);
      const uint32_t t0 = b.now;
      ASSERT_TRUE(wait_rdy(b, d, 10000));
      // ceil(cycles x 32768 / 6.144 MHz): the data sheet's (128 FW + 249) or (64 FW + 206).
      const double cycles = chop ? 128.0 * fw + 249.0 : 64.0 * fw + 206.0;
      EXPECT_EQ(b.now - t0, static_cast<uint32_t>(std::ceil(cycles * 32768.0 / 6.144e6)))
          << chop << " " << int{fw};
      int32_t c = 0;
      uint8_t st = 0;
      ASSERT_EQ(d.read_result(0, &c, &st), fw::status::ok);
    }
  }
  // FW = 94 with chop is the paper's 2 ms conversion (500.3 Hz).
  EXPECT_NEAR(a::conversion_mclk(true, 94) / 6.144e6, 1.9989e-3, 1e-7);
}

TEST(Ad7739Driver, AMissingRdyIsATimeoutNotAHang) {
  code_list src{{5}};
  host_board b(&code_list::call, &src);
  a::driver d(b.hw());
  b.adc.withhold_rdy(0, 1);
  ASSERT_EQ(d.start_single(0), fw::status::ok);
  EXPECT_FALSE(wait_rdy(b, d, 5000));
  // The next conversion is not affected.
  ASSERT_EQ(d.start_single(0), fw::status::ok);
  EXPECT_TRUE(wait_rdy(b, d, 5000));
}

TEST(Stepper, FullStepSequenceBothWays) {
  stepper::motor m;
  m.energised = true;
  std::vector<uint8_t> seen;
  for (int i = 0; i < 5; ++i) {
    m.step(1);
    seen.push_back(m.nibble());
  }
  EXPECT_EQ(seen, (std::vector<uint8_t>{0x6, 0xC, 0x9, 0x3, 0x6}));
  EXPECT_EQ(m.position, 5);
  seen.clear();
  for (int i = 0; i < 5; ++i) {
    m.step(-1);
    seen.push_back(m.nibble());
  }
  EXPECT_EQ(seen, (std::vector<uint8_t>{0x3, 0x9, 0xC, 0x6, 0x3}));
  EXPECT_EQ(m.position, 0);
  stepper::motor off;
  EXPECT_EQ(off.nibble(), 0);
}

TEST(Stepper, TwoMotorsOnOnePortKeepTheirNibbles) {
  stepper::motor low;
  stepper::motor high;
  low.energised = high.energised = true;
  uint32_t x = 1;
  for (int i = 0; i < 2000; ++i) {
    x = x * 1664525u + 1013904223u;
    stepper::motor& m = (x >> 31) != 0 ? low : high;
    const uint8_t other_before =
        static_cast<uint8_t>(stepper::port_byte(low, high) & (&m == &low ? 0xF0 : 0x0F));
    m.step((x >> 30 & 1u) != 0 ? 1 : -1);
    const uint8_t other_after =
        static_cast<uint8_t>(stepper::port_byte(low, high) & (&m == &low ? 0xF0 : 0x0F));
    ASSERT_EQ(other_before, other_after) << i;
  }
  EXPECT_EQ(stepper::port_byte(low, high), low.nibble() | (high.nibble() << 4));
}

// Drives a move as a port without a step timer does (device::step_turn): the queue refilled,
// the step taken when due, one per poll; returns the ticks of the steps.
std::vector<uint32_t> run_move(stepper::mover& mv, const stepper::ramp_plan& p, host_board& b,
                               stepper::motor& flip, stepper::motor& other, stepper::follower rule,
                               uint32_t poll_every = 1, std::size_t max_steps = 1u << 20) {
  std::vector<uint32_t> at;
  for (int guard = 0; mv.busy() && at.size() < max_steps && guard < 10000000;
       ++guard, b.now += poll_every) {
    mv.refill(p);
    if (mv.paused()) mv.rebase(b.now, p);
    if (static_cast<int32_t>(b.now - mv.next_due()) < 0) continue;
    uint32_t next = 0;
    mv.take_step(flip, other, rule, b.now, &next);
    b.hw().stepper_port(stepper::port_byte(flip, other));
    at.push_back(b.now);
  }
  return at;
}

TEST(Stepper, AHalfTurnIsHalfARevolutionOfSteps) {
  code_list src{{0}};
  host_board b(&code_list::call, &src);
  stepper::motor flip;
  stepper::motor other;
  stepper::mover mv;
  const auto plan = stepper::make_plan({100, 400, 2000}, host_board::tick_hz);
  flip.energised = other.energised = true;  // coils on at their phase first (no step)
  b.hw().stepper_port(stepper::port_byte(flip, other));
  mv.begin(100, b.now, plan);  // 180 deg of a 200-step motor
  run_move(mv, plan, b, flip, other, stepper::follower::opposite);
  EXPECT_EQ(mv.steps_done(), 100u);
  EXPECT_EQ(b.motors.position[0], 100);
  EXPECT_EQ(b.motors.position[1], -100);
  EXPECT_EQ(b.motors.bad_transitions, 0u);
  EXPECT_EQ(mv.rebases(), 0u);
}

// The intervals the device computes per step in 32 bits (ramp_plan) are the reference formula's
// (64-bit square root, step_interval) for every step of every move: random ramps over the whole
// CONFIGURE range, both tick rates of the ports.
TEST(Stepper, PlanIntervalsEqualTheReferenceFormula) {
  std::uint32_t x = 7;
  const auto next = [&] {
    x = x * 1664525u + 1013904223u;
    return x >> 8;
  };
  int moves = 0;
  for (const std::uint32_t tick_hz : {32768u, 1000000u}) {
    for (int i = 0; i < 400; ++i) {
      const auto top = static_cast<std::uint16_t>(1 + next() % 5000);
      const auto start = static_cast<std::uint16_t>(1 + next() % top);
      const auto accel =
          static_cast<std::uint16_t>(i % 5 == 0 ? 1 + next() % 20 : 1 + next() % 65535);
      const stepper::ramp r{start, top, accel};
      const auto plan = stepper::make_plan(r, tick_hz);
      const std::uint32_t n = i % 7 == 0 ? 1 + next() % 65535 : 1 + next() % 4000;
      const std::uint32_t stride = n > 5000 ? 37 : 1;
      for (std::uint32_t k = 0; k < n; k += stride)
        ASSERT_EQ(stepper::interval(plan, k, n), stepper::step_interval(r, k, n, tick_hz))
            << "ramp " << start << " " << top << " " << accel << ", step " << k << " of " << n;
      ++moves;
    }
  }
  EXPECT_EQ(moves, 800);
}

// The mover computes its queued intervals from a running square root (adds and compares, no
// isqrt per step: the F149 could not compute them at the top of a 2 000-steps/s ramp): every
// step of every move, triangles and trapezoids, over the CONFIGURE range, is timed by the
// reference formula, and after a pause the new ramp's steps are the reference's again.
TEST(Stepper, TheMoversRunningRootGivesTheReferenceIntervals) {
  std::uint32_t x = 11;
  const auto next = [&] {
    x = x * 1664525u + 1013904223u;
    return x >> 8;
  };
  // 32 768 Hz (the F149, the host port: the 16-bit running root and interval, where 2a < 2^16),
  // 1 MHz (the Cortex-M3 image: the 32-bit code) and 20 000 Hz (16-bit, the lowest tick rate
  // the 16-bit interval takes).
  for (int i = 0; i < 600; ++i) {
    const std::uint32_t tick_hz = i % 3 == 0 ? 32768u : i % 3 == 1 ? 1000000u : 20000u;
    // Intervals within 16 bits, as CONFIGURE requires (the slowest start rate 16 steps/s at 1 MHz).
    const std::uint32_t slowest = tick_hz / 0xFFFFu + 1;
    const auto top = static_cast<std::uint16_t>(slowest + next() % 5000);
    const auto start = static_cast<std::uint16_t>(slowest + next() % (top - slowest + 1));
    const auto accel =
        static_cast<std::uint16_t>(i % 5 == 0 ? 1 + next() % 20 : 1 + next() % 65535);
    const stepper::ramp r{start, top, accel};
    const auto plan = stepper::make_plan(r, tick_hz);
    const auto n = static_cast<std::uint16_t>(2 + next() % 3000);
    stepper::motor flip, other;
    stepper::mover mv;
    mv.begin(i % 2 == 0 ? n : -n, 0, plan);
    std::uint32_t now = 0, due = 0;
    const std::uint32_t pause_at = i % 3 == 0 ? next() % n : n;  // a starved queue, then a rebase
    std::uint32_t base = 0;
    for (std::uint32_t k = 0; k + 1 < n; ++k) {
      mv.refill(plan);
      if (k == pause_at) {
        // Take the steps the queue holds without refilling: the move pauses, then resumes
        // with a new ramp from standstill for the steps left.
        while (mv.take_step(flip, other, stepper::follower::off, now, &due)) now = due;
        if (!mv.busy()) break;
        ASSERT_TRUE(mv.paused());
        base = mv.steps_done();
        k = base;
        mv.rebase(now, plan);
        if (k + 1 >= n) break;
      }
      ASSERT_TRUE(mv.take_step(flip, other, stepper::follower::off, now, &due)) << k;
      ASSERT_EQ(due - now, stepper::step_interval(r, k - base, n - base, tick_hz))
          << "ramp " << start << " " << top << " " << accel << ", step " << k << " of " << n
          << " (a new ramp at " << base << ")";
      now = due;
    }
  }
}

// A main loop that looks only every 1000 ticks (steps are due every ~80) and then every tick
// again: each late poll takes one step and times the next from then, so the port never skips a
// phase and the late steps never come in a burst once the polls are frequent again (the
// review of issue 32: a late mover caught up at the poll rate).
TEST(Stepper, ALatePollTakesOneStepAndTheNextComesAnIntervalLater) {
  code_list src{{0}};
  host_board b(&code_list::call, &src);
  stepper::motor flip;
  stepper::motor other;
  flip.energised = true;
  b.hw().stepper_port(stepper::port_byte(flip, other));
  stepper::mover mv;
  const auto plan = stepper::make_plan({100, 400, 2000}, host_board::tick_hz);
  mv.begin(-50, 0, plan);
  const auto late = run_move(mv, plan, b, flip, other, stepper::follower::off, 1000, 20);
  ASSERT_EQ(late.size(), 20u);  // 20 polls of the 1000-tick loop took 20 steps
  for (std::size_t i = 1; i < late.size(); ++i) EXPECT_EQ(late[i] - late[i - 1], 1000u);
  // Then the loop is fast again: the remaining 30 steps keep at least the cruise interval.
  const auto fast = run_move(mv, plan, b, flip, other, stepper::follower::off, 1);
  ASSERT_EQ(fast.size(), 30u);
  EXPECT_GE(fast.front() - late.back(), plan.cruise_ticks);
  for (std::size_t i = 1; i < fast.size(); ++i)
    EXPECT_GE(fast[i] - fast[i - 1], plan.cruise_ticks) << i;
  EXPECT_EQ(b.motors.position[0], -50);
  EXPECT_EQ(b.motors.bad_transitions, 0u);
}

// A consumer (the step timer's interrupt) that finds no interval queued pauses the move; the
// main loop then starts a new ramp from standstill for the steps left: the first interval after
// the pause is the start rate's, never the top rate's.
TEST(Stepper, AStarvedMoveResumesWithANewRampFromStandstill) {
  stepper::motor flip;
  stepper::motor other;
  stepper::mover mv;
  const stepper::ramp r{100, 400, 2000};
  const auto plan = stepper::make_plan(r, 32768);
  // The queue holds at most queue_len intervals, and no more than a full queue's time at the
  // top rate: here (slow start-rate intervals) 3.
  mv.begin(200, 0, plan);
  uint32_t now = 0;
  uint32_t next = 0;
  int taken = 0;
  while (mv.take_step(flip, other, stepper::follower::off, now, &next)) {
    now = next;
    ++taken;
  }
  EXPECT_EQ(taken, 3);  // one more step, then no interval queued
  EXPECT_TRUE(mv.paused());
  EXPECT_EQ(mv.steps_done(), 3u + 1u);
  now += 5000;  // the main loop comes back late
  mv.rebase(now, plan);
  EXPECT_FALSE(mv.paused());
  EXPECT_EQ(mv.next_due(), now);
  ASSERT_TRUE(mv.take_step(flip, other, stepper::follower::off, now, &next));
  const std::uint32_t left = 200 - 3 - 1;
  EXPECT_EQ(next - now, stepper::step_interval(r, 0, left, 32768));  // the start rate's
  EXPECT_EQ(next - now, 328u);                                       // 32768 / 100
  EXPECT_EQ(mv.rebases(), 1u);
  EXPECT_EQ(flip.position, 3 + 2);
}

TEST(Stepper, RampTimingMatchesTheTrapezoid) {
  // v^2 = v0^2 + 2 a s up to the top rate, symmetric down: the move's duration in closed form
  // is 2 (v_top - v0) / a + (n - 2 s_a) / v_top with s_a = (v_top^2 - v0^2) / (2 a).
  const stepper::ramp r{100, 400, 2000};
  const uint32_t n = 100;
  uint32_t ticks = 0;
  uint16_t prev = 0;
  for (uint32_t k = 0; k < n; ++k) {
    const uint16_t v = stepper::step_rate(r, k, n);
    if (k < n / 2) {
      EXPECT_GE(v, prev) << k;  // speeds up, then
    }
    EXPECT_EQ(v, stepper::step_rate(r, n - 1 - k, n)) << k;  // symmetric
    EXPECT_LE(v, 400);
    EXPECT_GE(v, 100);
    prev = v;
    if (k + 1 < n) ticks += stepper::step_interval(r, k, n, 32768);
  }
  EXPECT_EQ(stepper::step_rate(r, 0, n), 100);
  EXPECT_EQ(stepper::step_rate(r, 50, n), 400);
  const double s_a = (400.0 * 400 - 100.0 * 100) / (2 * 2000.0);
  const double t_closed = 2 * (400.0 - 100) / 2000 + (n - 2 * s_a) / 400;
  // Steps are discrete (the rate of a step holds until the next one): within 5 %.
  EXPECT_NEAR(ticks / 32768.0, t_closed, 0.05 * t_closed);
  // The paper: a turn takes about 1-2 s; the default (200 steps/rev) needs ~0.4 s.
  EXPECT_LT(ticks / 32768.0, 2.0);
}

}  // namespace
