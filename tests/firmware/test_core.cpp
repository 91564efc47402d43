// The firmware core on the host port (issue 8): the sequencer's dwells against the model's
// codes, on-board processing against the host library, RDY faults, a hostile link, commands,
// RAW blocks, turns, homing and the link budget.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "firmware/harness.hpp"
#include "firmware/protocol/budget.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/compensation.hpp"

namespace {

using namespace gyroflip;
using fw::testing::configure;
using fw::testing::quick_config;
using fw::testing::rig;
using protocol::configure_msg;
using protocol::dwell_msg;

bool has_dwells(const rig& r, size_t n) {
  return r.count<dwell_msg>() >= n;
}

// Sum, min and max of the model's gyro codes [first, first + n) at a position.
struct expect_sums {
  int64_t sum = 0;
  int32_t min = 0, max = 0;
};
expect_sums model_sums(const fw::testing::code_source& s, uint32_t first, uint32_t n, bool at_b) {
  expect_sums e;
  for (uint32_t k = first; k < first + n; ++k) {
    const int32_t c = s.gyro(k, at_b);
    e.sum += c;
    if (k == first || c < e.min) e.min = c;
    if (k == first || c > e.max) e.max = c;
  }
  return e;
}

class DwellMeans : public ::testing::TestWithParam<uint16_t> {};

TEST_P(DwellMeans, EqualTheModelsCodes) {
  const uint16_t n = GetParam();
  rig r;
  configure(r, quick_config(n));
  r.start();
  const size_t want = n > 1000 ? 2 : 6;
  ASSERT_TRUE(r.run_until([&] { return has_dwells(r, want); }, 12'000'000));
  const auto dwells = r.all<dwell_msg>();
  uint32_t index = 0;
  for (size_t i = 0; i < want; ++i) {
    const dwell_msg& d = dwells[i];
    SCOPED_TRACE(i);
    EXPECT_EQ(d.position, i % 2);
    EXPECT_EQ(d.cycle, i / 2);
    EXPECT_EQ(d.flags, 0);
    ASSERT_EQ(d.n, n);
    const expect_sums e = model_sums(r.source, index, n, d.position == 1);
    EXPECT_EQ(d.code_sum, e.sum);
    EXPECT_EQ(d.code_min, e.min);
    EXPECT_EQ(d.code_max, e.max);
    // n conversions of ceil(12281 MCLK x 32768 / 6.144 MHz) = 66 ticks each, at least.
    EXPECT_GE(d.t_end_ticks - d.t_start_ticks, 66u * n);
    EXPECT_LE(d.t_end_ticks - d.t_start_ticks, 68u * n + 2);
    index += n;
  }
}

INSTANTIATE_TEST_SUITE_P(N, DwellMeans,
                         ::testing::Values(uint16_t{1}, uint16_t{256},
                                           uint16_t{protocol::max_n_avg}));

TEST(FirmwareCore, CalibrationAndCompensationMatchTheHostLibrary) {
  rig r;
  r.source.noise_amp = 40000;  // a noisy gyro: r varies by hundreds of codes
  r.source.rate = 1234;
  configure_msg c = quick_config(32);
  c.flags = protocol::cfg_chop | protocol::cfg_compensate;
  configure(r, c);
  protocol::set_delta_n_msg dn;
  dn.delta_n_q8 = 98765;  // 385.8 codes
  r.send(dn);
  protocol::calibrate_msg cal;
  cal.cycles = 12;
  r.send(cal);
  ASSERT_TRUE(r.run_until([&] { return r.count<protocol::cal_result_msg>() == 1; }, 4'000'000));
  r.run(20000);
  EXPECT_EQ(r.dev.state(), protocol::device_state::idle);  // CALIBRATE from idle stops after

  const auto dwells = r.all<dwell_msg>();
  ASSERT_EQ(dwells.size(), 24u);
  std::vector<method::cycle> cycles;
  for (size_t i = 0; i + 1 < dwells.size(); i += 2) {
    const double ya = static_cast<double>(dwells[i].code_sum) / dwells[i].n;
    const double yb = static_cast<double>(dwells[i + 1].code_sum) / dwells[i + 1].n;
    cycles.push_back({0.0, (ya - yb) / 2, (ya + yb) / 2, method::no_value});
  }
  const auto host = method::calibrate(cycles);
  ASSERT_TRUE(host.ok());
  const auto dev = r.all<protocol::cal_result_msg>().front();
  EXPECT_EQ(dev.cycles, 12);
  EXPECT_NEAR(dev.delta_n_q8, 256 * host.value().delta_n_dps, 1.0);
  EXPECT_NEAR(static_cast<double>(dev.std_q8), 256 * host.value().std_dps, 1.0);
  EXPECT_GT(host.value().std_dps, 100.0);  // the spread is real, not zero
  EXPECT_EQ(r.dev.delta_n_q8(), dev.delta_n_q8);

  // COMPENSATED (paper eqn 12) used the dN sent before the calibration.
  const auto comp = r.all<protocol::compensated_msg>();
  ASSERT_EQ(comp.size(), cycles.size());
  for (size_t i = 0; i < comp.size(); ++i) {
    const method::compensated_cycle h =
        method::compensate(cycles[i], method::constant_model(dn.delta_n_q8 / 256.0));
    EXPECT_NEAR(comp[i].rate_q8, 256 * h.rate_dps, 1.0) << i;
    EXPECT_NEAR(comp[i].bias_q8, 256 * h.bias_dps, 1.0) << i;
    EXPECT_EQ(comp[i].cycle, i);
  }
}

TEST(FirmwareCore, CalibratorSpreadStaysExactForLargeSums) {
  // K = 65535 cycles alternating +-(2^24 - 1) q8 about a large offset: the shifted sums reach
  // their bounds; the mean and the spread still come out exact.
  fw::calibrator c;
  c.begin(65535);
  const int32_t base = 2000000000;
  const int32_t amp = (1 << 23) - 1;  // d = 0 or -2 amp, |d| < 2^24
  bool done = false;
  for (uint32_t k = 0; k < 65535; ++k) done = c.add(k % 2 == 0 ? base : base - 2 * amp, 0);
  ASSERT_TRUE(done);
  const auto res = c.result();
  // mean = base - 2 amp * 32767 / 65535; sample std of a two-valued series.
  const double n = 65535;
  const double m = base - 2.0 * amp * 32767 / n;
  const double var =
      (32768 * std::pow(base - m, 2) + 32767 * std::pow(base - 2.0 * amp - m, 2)) / (n - 1);
  EXPECT_NEAR(res.delta_n_q8, m, 0.5);
  EXPECT_NEAR(static_cast<double>(res.std_q8), std::sqrt(var), 0.5);
  // Past the bound the spread is reported as saturated, never wrapped.
  c.begin(3);
  c.add(0, 0);
  c.add(1 << 24, 0);
  c.add(0, 0);
  EXPECT_EQ(c.result().std_q8, 0xFFFFFFFFu);
}

TEST(FirmwareCore, AMissingRdyIsFlaggedReportedAndTheRunGoesOn) {
  rig r;
  const uint16_t n = 64;
  configure(r, quick_config(n));
  r.board.adc.withhold_rdy(10, 1);
  r.start();
  ASSERT_TRUE(r.run_until([&] { return has_dwells(r, 4); }, 2'000'000));
  const auto dwells = r.all<dwell_msg>();
  EXPECT_EQ(dwells[0].flags, protocol::dwell_rdy_timeout);
  EXPECT_EQ(dwells[0].n, n - 1);
  // The withheld conversion never finished, so the model's next code is index 10 again.
  EXPECT_EQ(dwells[0].code_sum, model_sums(r.source, 0, n - 1, false).sum);
  EXPECT_EQ(dwells[1].flags, 0);
  EXPECT_EQ(dwells[1].n, n);
  EXPECT_EQ(dwells[1].code_sum, model_sums(r.source, n - 1, n, true).sum);
  const auto errors = r.all<protocol::error_msg>();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].code, static_cast<uint8_t>(protocol::status::timeout));
  EXPECT_EQ(errors[0].what, static_cast<uint8_t>(protocol::error_source::adc));
  EXPECT_EQ(r.dev.counters().rdy_timeouts, 1);
  // The timeout is three conversion times, not a hang: the dwell took ~ (n + 3) conversions.
  EXPECT_LE(dwells[0].t_end_ticks - dwells[0].t_start_ticks, 67u * (n + 3) + 4);
}

TEST(FirmwareCore, JunkAndBadCommandsNeverStopAcquisition) {
  const configure_msg c = quick_config(64);
  rig clean;
  configure(clean, c);
  clean.start();
  clean.run(300000);

  rig noisy;
  configure(noisy, c);
  noisy.start();
  uint32_t x = 7;
  std::vector<uint8_t> junk;
  for (int burst = 0; burst < 300; ++burst) {
    junk.clear();
    for (int i = 0; i < 40; ++i) {
      x = x * 1664525u + 1013904223u;
      junk.push_back(static_cast<uint8_t>(x >> 24));
    }
    junk.insert(junk.end(), 4, 0);  // a delimiter run: the junk ends as one bad frame
    noisy.send_bytes(junk);
    if (burst % 50 == 0) {
      noisy.send(c);              // CONFIGURE while running: refused, busy
      const uint8_t bad[] = {1};  // a START with one payload byte: not its layout
      uint8_t buf[protocol::max_wire];
      const size_t len =
          protocol::encode_frame(0x22, static_cast<uint16_t>(999 + burst), bad, 1, buf, sizeof buf);
      noisy.send_cobs(buf, len);
    }
    noisy.run(1000);
  }
  // Same dwells, same values, at the same times as without the junk.
  const auto a = clean.all<dwell_msg>();
  const auto b = noisy.all<dwell_msg>();
  ASSERT_GT(a.size(), 10u);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << i;
  size_t busy = 0;
  size_t bad_frame = 0;
  for (const auto& nk : noisy.all<protocol::nak_msg>()) {
    busy += nk.reason == static_cast<uint8_t>(protocol::status::busy) ? 1 : 0;
    bad_frame += nk.reason == static_cast<uint8_t>(protocol::status::bad_frame) ? 1 : 0;
  }
  EXPECT_EQ(busy, 6u);
  EXPECT_EQ(bad_frame, 6u);
  noisy.send(protocol::stop_msg{});
  noisy.run(2000);
  const auto st = noisy.last<protocol::status_msg>();
  EXPECT_GE(st.rx_errors, 250);  // most junk bursts end in a bad frame
  EXPECT_EQ(noisy.dev.state(), protocol::device_state::idle);
}

TEST(FirmwareCore, PingConfigureStartStop) {
  rig r;
  // INFO at boot.
  ASSERT_EQ(r.count<protocol::info_msg>(), 1u);
  const uint16_t ps = r.send(protocol::ping_msg{});
  r.run(1000);
  const auto ack = r.last<protocol::ack_msg>();
  EXPECT_EQ(ack.seq, ps);
  EXPECT_EQ(ack.of_type, static_cast<uint8_t>(protocol::msg::ping));
  const auto info = r.last<protocol::info_msg>();
  EXPECT_EQ(info.protocol, protocol::protocol_version);
  EXPECT_EQ(info.tick_hz, 32768u);
  EXPECT_EQ(info.mclk_hz, 6144000u);
  EXPECT_EQ(info.adc_revision, fw::model::ad7739_model::revision);
  EXPECT_EQ(info.serial, 12345u);
  EXPECT_EQ(info.config, configure_msg{});

  configure_msg bad;
  bad.n_avg = 0;
  r.send(bad);
  configure_msg fast = quick_config(1);
  fast.flags = protocol::cfg_chop | protocol::cfg_raw;
  fast.pos_steps[1] = 1;
  fast.step_rate_sps = 5000;
  fast.settle_ms = 0;
  fast.filter_word = 2;
  r.send(fast);  // ~4 dwells per ms: beyond the link
  r.run(1000);
  const auto naks = r.all<protocol::nak_msg>();
  ASSERT_EQ(naks.size(), 2u);
  for (const auto& nk : naks) EXPECT_EQ(nk.reason, static_cast<uint8_t>(protocol::status::bad_arg));
  EXPECT_GT(protocol::worst_bytes_per_s(fast, 6144000), protocol::link_bytes_per_s);

  configure_msg good = quick_config(16);
  good.other_motor = static_cast<uint8_t>(protocol::other_motor::hold);
  configure(r, good);
  r.send(protocol::ping_msg{});
  r.run(1000);
  EXPECT_EQ(r.last<protocol::info_msg>().config, good);

  r.start();
  r.run(100);
  EXPECT_EQ(r.dev.state(), protocol::device_state::running);
  ASSERT_TRUE(r.run_until([&] { return has_dwells(r, 3); }, 1'000'000));
  r.send(protocol::stop_msg{});
  r.run(2000);
  const size_t after_stop = r.count<dwell_msg>();
  EXPECT_EQ(r.dev.state(), protocol::device_state::idle);
  EXPECT_EQ(r.last<protocol::status_msg>().state, 0);
  r.run(100000);
  EXPECT_EQ(r.count<dwell_msg>(), after_stop);
  // Sequence numbers of the device's frames: none missing, none repeated.
  EXPECT_EQ(r.decoder.counts().missing, 0u);
  EXPECT_EQ(r.decoder.counts().duplicates, 0u);
  EXPECT_EQ(r.decoder.counts().bad(), 0u);
}

TEST(FirmwareCore, RawBlocksCarryEveryConversion) {
  rig r;
  configure_msg c = quick_config(256);
  c.flags = protocol::cfg_chop | protocol::cfg_raw;
  c.status_period_ms = 1000;
  configure(r, c);
  r.start();
  ASSERT_TRUE(r.run_until([&] { return has_dwells(r, 4); }, 2'000'000));
  const auto dwells = r.all<dwell_msg>();
  std::vector<protocol::raw_msg> raws = r.all<protocol::raw_msg>();
  ASSERT_GE(raws.size(), 16u);
  uint32_t index = 0;
  for (size_t i = 0; i < 16; ++i) {
    const auto& m = raws[i];
    ASSERT_EQ(m.first_index, index);
    ASSERT_EQ(m.count, protocol::raw_msg::max_codes);
    const bool at_b = dwells[i / (256 / protocol::raw_msg::max_codes)].position == 1;
    for (uint8_t k = 0; k < m.count; ++k) ASSERT_EQ(m.code(k), r.source.gyro(index + k, at_b));
    index += m.count;
  }
  for (const auto& d : dwells) EXPECT_EQ(d.flags & protocol::dwell_raw_dropped, 0);
  EXPECT_EQ(r.dev.counters().frames_dropped, 0);
}

// The PWM accelerometer interface: each DWELL carries the summed T1 and T2 of the periods captured
// during that dwell only (not the turn's), and the host's conversion gives the datasheet's g.
TEST(FirmwareCore, DwellsCarryTheAccelerometersDutyCycles) {
  rig r;
  constexpr uint32_t period = 25;  // ticks (2 ms at the rig's 12 345 Hz tick)
  r.board.pwm_high_ticks[0] = 14;  // 56 % duty: (0.56 - 0.5) / 0.125 = +0.48 g
  r.board.pwm_high_ticks[1] = 12;  // 48 % duty: -0.16 g
  r.board.pwm_period_ticks[0] = r.board.pwm_period_ticks[1] = period;
  configure(r, quick_config(64));
  r.start();
  ASSERT_TRUE(r.run_until([&] { return has_dwells(r, 4); }, 2'000'000));
  for (const dwell_msg& d : r.all<dwell_msg>()) {
    SCOPED_TRACE(d.cycle * 2 + d.position);
    ASSERT_EQ(d.ax_period_ticks % period, 0u);
    const uint32_t periods = d.ax_period_ticks / period;
    EXPECT_EQ(d.ax_high_ticks, 14 * periods);
    EXPECT_EQ(d.ay_period_ticks, d.ax_period_ticks);
    EXPECT_EQ(d.ay_high_ticks, 12 * periods);
    // Every period that ended inside the dwell, give or take the one at each edge.
    const uint32_t span = (d.t_end_ticks - d.t_start_ticks) / period;
    EXPECT_GE(periods + 1, span);
    EXPECT_LE(periods, span + 1);
    EXPECT_EQ(protocol::adxl202_accel_mg(d.ax_high_ticks, d.ax_period_ticks), 480);
    EXPECT_EQ(protocol::adxl202_accel_mg(d.ay_high_ticks, d.ay_period_ticks), -160);
  }
  // No accelerometer wired: the fields stay zero and read as no acceleration.
  rig bare;
  configure(bare, quick_config(16));
  bare.start();
  ASSERT_TRUE(bare.run_until([&] { return has_dwells(bare, 2); }, 2'000'000));
  for (const dwell_msg& d : bare.all<dwell_msg>()) {
    EXPECT_EQ(d.ax_period_ticks, 0u);
    EXPECT_EQ(d.ay_high_ticks, 0u);
    EXPECT_EQ(protocol::adxl202_accel_mg(d.ax_high_ticks, d.ax_period_ticks), 0);
  }
}

TEST(FirmwareCore, TurnsBackAndForthOrOneWayAndTheSecondMotorFollowsItsRule) {
  struct expect {
    protocol::other_motor rule;
    bool one_way;
  };
  for (const expect e :
       {expect{protocol::other_motor::off, false}, expect{protocol::other_motor::hold, false},
        expect{protocol::other_motor::same, true}, expect{protocol::other_motor::opposite, true}}) {
    SCOPED_TRACE(static_cast<int>(e.rule));
    rig r;
    configure_msg c = quick_config(8);
    c.other_motor = static_cast<uint8_t>(e.rule);
    if (e.one_way) c.flags |= protocol::cfg_one_way;
    configure(r, c);
    r.start();
    ASSERT_TRUE(r.run_until([&] { return has_dwells(r, 6); }, 2'000'000));
    // Where the table stood at the first conversion of each dwell.
    for (size_t i = 0; i < 6; ++i) {
      const int32_t want = e.one_way ? static_cast<int32_t>(100 * i) : (i % 2 == 0 ? 0 : 100);
      EXPECT_EQ(r.positions.at(8 * i), want) << i;
    }
    r.send(protocol::stop_msg{});
    r.run(2000);
    const int32_t m0 = r.board.motors.position[0];
    const uint8_t nib1 = static_cast<uint8_t>(r.board.motors.port >> 4);
    switch (e.rule) {
      case protocol::other_motor::off:
        EXPECT_EQ(nib1, 0);
        break;
      case protocol::other_motor::hold:
        EXPECT_NE(nib1, 0);
        EXPECT_EQ(r.board.motors.position[1], 0);
        break;
      case protocol::other_motor::same:
        EXPECT_EQ(r.board.motors.position[1], m0);
        break;
      case protocol::other_motor::opposite:
        EXPECT_EQ(r.board.motors.position[1], -m0);
        break;
    }
    EXPECT_EQ(r.board.motors.bad_transitions, 0u);
  }
}

TEST(FirmwareCore, HomesBeforeTheRunAndReportsAMissingSwitch) {
  {
    rig r;
    r.board.home_at = -37;
    r.source.home_offset = -37;
    configure_msg c = quick_config(8);
    c.flags |= protocol::cfg_home;
    configure(r, c);
    r.start();
    ASSERT_TRUE(r.run_until([&] { return has_dwells(r, 2); }, 2'000'000));
    EXPECT_EQ(r.positions.at(0), -37);        // A is home
    EXPECT_EQ(r.positions.at(8), -37 + 100);  // B, counted from home
    for (const auto& d : r.all<dwell_msg>()) EXPECT_EQ(d.flags, 0);
  }
  {
    rig r;
    r.board.has_home = false;
    configure_msg c = quick_config(8);
    c.flags |= protocol::cfg_home;
    configure(r, c);
    r.start();
    ASSERT_TRUE(r.run_until([&] { return has_dwells(r, 2); }, 2'000'000));
    const auto d = r.all<dwell_msg>();
    EXPECT_EQ(d[0].flags, protocol::dwell_step_fault);
    EXPECT_EQ(d[1].flags, 0);
    ASSERT_EQ(r.count<protocol::error_msg>(), 1u);
    EXPECT_EQ(r.all<protocol::error_msg>()[0].what,
              static_cast<uint8_t>(protocol::error_source::stepper));
  }
}

TEST(LinkBudget, WireSizesAreTheEncodedSizes) {
  // A frame of p payload bytes: header 5 + p + CRC 2 and one COBS byte, each as two wire bytes,
  // then a run of 4 zero bytes (10 after a last nibble 0): at most 2 p + 26 (docs/PROTOCOL.md).
  uint8_t buf[protocol::max_wire_bytes];
  const auto check = [&](const auto& m, uint32_t payload) {
    const size_t n = protocol::encode_wire(m, 0, buf, sizeof buf);
    EXPECT_TRUE(n == 2 * (payload + 8) + 4 || n == 2 * (payload + 8) + 10) << n;
    EXPECT_LE(n, protocol::line_bytes(payload));
    EXPECT_EQ(protocol::line_bytes(payload), 2 * payload + 26);
  };
  protocol::raw_msg raw;
  raw.count = protocol::raw_msg::max_codes;
  check(raw, protocol::raw_payload(32));
  check(dwell_msg{}, protocol::dwell_payload);
  check(protocol::status_msg{}, protocol::status_payload);
  check(protocol::compensated_msg{}, protocol::compensated_payload);
}

TEST(LinkBudget, RawAt500HzWithDwellsAndStatusLeavesThirtyPercent) {
  // The paper's configuration with every option that sends: RAW, COMPENSATED, STATUS at 1 Hz.
  configure_msg c;
  c.flags = protocol::cfg_chop | protocol::cfg_raw | protocol::cfg_compensate;
  const double link = protocol::link_bytes_per_s;
  EXPECT_EQ(protocol::link_bytes_per_s, 11520u);
  // Conversions back to back at 500.3 Hz (no turn at all), each frame at its longest (2 p + 26
  // wire bytes): RAW 228 B per 32 codes, DWELL 124 B and half a COMPENSATED (52 B) per 256
  // codes, STATUS 104 B/s (docs/PROTOCOL.md).
  const double conv_hz = 6.144e6 / 12281;
  const double sustained = conv_hz * (228.0 / 32 + (124 + 52 / 2.0) / 256) + 104;
  EXPECT_NEAR(sustained, 3962, 1);
  EXPECT_LE(sustained, 0.7 * link);
  // The device's own bound (with the turn and the settling) is lower still.
  EXPECT_LE(protocol::worst_bytes_per_s(c, 6144000), sustained);
  EXPECT_EQ(protocol::check_configure(c, 6144000), protocol::status::ok);
  // The shortest dwells there are (RAW, 4 temperature conversions, a 1-step turn at 5000
  // steps/s, no settling): a dwell of n_avg codes sends DWELL 124 B, RAW 2 (5 + 3 n) + 26 B, half
  // a COMPENSATED 26 B in (n + 4) conversions + 0.2 ms, plus STATUS 104 B/s.
  const auto by_hand = [&](unsigned n) {
    const double bytes = 124 + 2.0 * (5 + 3 * n) + 26 + 26;
    return bytes / ((n + 4) * 12281 / 6.144e6 + 1 / 5000.0) + 104;
  };
  configure_msg tight = c;
  tight.settle_ms = 0;
  tight.pos_steps[1] = 1;
  tight.step_rate_sps = protocol::max_step_rate_sps;
  for (const uint16_t n : {uint16_t{4}, uint16_t{8}, uint16_t{16}}) {
    tight.n_avg = n;
    EXPECT_NEAR(protocol::worst_bytes_per_s(tight, 6144000), by_hand(n), 1.0) << n;
  }
  tight.n_avg = 16;  // keeps 30 % headroom
  EXPECT_LE(protocol::worst_bytes_per_s(tight, 6144000), 0.7 * link);
  tight.n_avg = 8;  // still fits the link: accepted
  EXPECT_EQ(protocol::check_configure(tight, 6144000), protocol::status::ok);
  tight.n_avg = 4;  // does not: refused
  EXPECT_GT(protocol::worst_bytes_per_s(tight, 6144000), link);
  EXPECT_EQ(protocol::check_configure(tight, 6144000), protocol::status::bad_arg);
}

TEST(LinkBudget, TheDeviceDropsRawFirstWhenTheLinkFallsBehind) {
  // The UART stalls for 2 s (a host that stopped reading with flow control, a stuck line):
  // the transmit ring fills, RAW blocks are dropped and counted, DWELLs are kept.
  rig r;
  configure_msg c = quick_config(256);
  c.flags = protocol::cfg_chop | protocol::cfg_raw;
  configure(r, c);
  r.start();
  r.board.uart_stalled = true;
  r.run(2 * 32768);
  r.board.uart_stalled = false;
  r.run(6 * 32768);
  const auto dwells = r.all<dwell_msg>();
  ASSERT_GE(dwells.size(), 6u);
  uint32_t flagged = 0;
  for (size_t i = 0; i < dwells.size(); ++i) {
    EXPECT_EQ(dwells[i].cycle, i / 2) << "a DWELL was lost";
    flagged += (dwells[i].flags & protocol::dwell_raw_dropped) != 0 ? 1u : 0u;
  }
  EXPECT_GE(flagged, 2u);
  const uint16_t dropped = r.dev.counters().frames_dropped;
  EXPECT_GT(dropped, 0);
  // Every dropped frame used a sequence number: the host sees exactly that many missing.
  EXPECT_EQ(r.decoder.counts().missing, dropped);
  EXPECT_EQ(r.decoder.counts().bad(), 0u);
}

}  // namespace
