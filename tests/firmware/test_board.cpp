// The board facts of issue 20 on the host port (docs/HARDWARE.md, FIRMWARE.md, PROTOCOL.md):
// RESEND and GONE, commands executed once, NAK for a damaged command, the angle table, the
// coils' holding current, homing through bounce and noise, the watchdog fed on progress, clock
// faults, failed conversion starts, and what INFO and STATUS say about the board.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "firmware/core/nv_record.hpp"
#include "firmware/harness.hpp"
#include "firmware/ports/msp430f149/limits.hpp"

namespace {

using namespace gyroflip;
using fw::testing::configure;
using fw::testing::quick_config;
using fw::testing::rig;
using protocol::configure_msg;
using protocol::dwell_msg;

// The frames of type M the device sent, with their sequence numbers.
template <class M>
std::vector<const rig::received*> frames_of(const rig& r, size_t from = 0) {
  std::vector<const rig::received*> out;
  for (size_t i = from; i < r.frames.size(); ++i)
    if (r.frames[i].type == static_cast<uint8_t>(M::type)) out.push_back(&r.frames[i]);
  return out;
}

protocol::resend_msg resend_of(std::initializer_list<uint16_t> seqs) {
  protocol::resend_msg m;
  for (const uint16_t s : seqs) m.seqs[m.count++] = s;
  return m;
}

// A run of at least `dwells` DWELLs of n_avg conversions, then STOP.
void record_dwells(rig& r, uint16_t n_avg, size_t dwells) {
  configure(r, quick_config(n_avg));
  r.start();
  ASSERT_TRUE(r.run_until([&] { return r.count<dwell_msg>() >= dwells; }, 2'000'000));
  r.send(protocol::stop_msg{});
  r.run(2000);
}

TEST(BoardLink, ResendBringsADwellBackWithItsNumberAndNamesWhatIsGone) {
  rig r;
  record_dwells(r, 32, 3);
  const auto dwells = frames_of<dwell_msg>(r);
  const rig::received first = *dwells[0];
  const uint16_t info_seq = r.frames[0].seq;  // the boot INFO: an answer, never resent
  ASSERT_EQ(r.frames[0].type, static_cast<uint8_t>(protocol::msg::info));
  const uint16_t next = static_cast<uint16_t>(r.frames.back().seq + 1);
  const size_t before = r.frames.size();
  // A number the device has not sent yet (a host probing past what it heard) gets no answer.
  r.send(resend_of({first.seq, info_seq, static_cast<uint16_t>(next + 3)}));
  r.run(3000);
  const auto again = frames_of<dwell_msg>(r, before);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0]->seq, first.seq);
  EXPECT_EQ(again[0]->payload, first.payload);
  const auto gone = frames_of<protocol::gone_msg>(r, before);
  ASSERT_EQ(gone.size(), 1u);
  const auto g = gone[0]->as<protocol::gone_msg>();
  ASSERT_EQ(g.count, 1u);
  EXPECT_EQ(g.seqs[0], info_seq);
  EXPECT_EQ(r.dev.counters().retransmits, 1u);
  // Nothing but the DWELL and the GONE answered (a RESEND is not acknowledged).
  EXPECT_EQ(r.frames.size(), before + 2);
}

TEST(BoardLink, ADwellTheHistoryOverwroteIsGone) {
  rig r;
  record_dwells(r, 16, 12);  // the history holds 7 DWELLs (fw::history_bytes)
  const auto dwells = frames_of<dwell_msg>(r);
  const uint16_t oldest = dwells.front()->seq;
  const uint16_t newest = dwells.back()->seq;
  const size_t before = r.frames.size();
  r.send(resend_of({oldest, newest}));
  r.run(3000);
  const auto again = frames_of<dwell_msg>(r, before);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0]->seq, newest);
  const auto gone = frames_of<protocol::gone_msg>(r, before);
  ASSERT_EQ(gone.size(), 1u);
  EXPECT_EQ(gone[0]->as<protocol::gone_msg>().seqs[0], oldest);
  // STATUS names the oldest number RESEND can still bring back.
  r.send(protocol::ping_msg{});  // (PING answers INFO; STATUS comes with STOP)
  r.send(protocol::stop_msg{});
  r.run(3000);
  const auto st = r.last<protocol::status_msg>();
  EXPECT_GT(static_cast<uint16_t>(st.history_oldest - oldest), 0u);
  EXPECT_LE(static_cast<uint16_t>(st.history_oldest - oldest),
            static_cast<uint16_t>(newest - oldest));
}

// A retried command (its ACK was lost) is answered again with the first answer's at_seq and is
// not executed again: a retried CALIBRATE does not restart the calibration, a retried START
// does not restart the run. Reference: the same rig with each command sent once.
TEST(BoardCommands, ARetriedCommandIsAnsweredAgainNotExecutedAgain) {
  const configure_msg c = quick_config(32);
  protocol::calibrate_msg cal;
  cal.cycles = 6;
  rig once;
  configure(once, c);
  once.send(cal);
  ASSERT_TRUE(
      once.run_until([&] { return once.count<protocol::cal_result_msg>() >= 1; }, 3'000'000));

  rig twice;
  configure(twice, c);
  const uint16_t s = twice.send(cal);
  ASSERT_TRUE(twice.run_until([&] { return twice.count<dwell_msg>() >= 5; }, 3'000'000));
  twice.send_as(cal, s);  // the same number, type and payload: a retry
  ASSERT_TRUE(
      twice.run_until([&] { return twice.count<protocol::cal_result_msg>() >= 1; }, 3'000'000));
  twice.run(5000);
  std::vector<protocol::ack_msg> cal_acks;
  for (const auto& a : twice.all<protocol::ack_msg>())
    if (a.seq == s) cal_acks.push_back(a);
  ASSERT_EQ(cal_acks.size(), 2u);
  EXPECT_EQ(cal_acks[1].at_seq, cal_acks[0].at_seq);
  const auto r1 = once.last<protocol::cal_result_msg>();
  const auto r2 = twice.last<protocol::cal_result_msg>();
  EXPECT_EQ(r2, r1);
  EXPECT_EQ(twice.count<protocol::cal_result_msg>(), 1u);
  EXPECT_EQ(twice.all<dwell_msg>(), once.all<dwell_msg>());  // same dwells, same times

  // START: a retry while running is acknowledged at the first ACK's number; cycles go on.
  rig run;
  configure(run, c);
  const uint16_t st = run.start();
  ASSERT_TRUE(run.run_until([&] { return run.count<dwell_msg>() >= 4; }, 3'000'000));
  protocol::start_msg m;
  m.config_crc = protocol::configure_crc(run.dev.config());
  run.send_as(m, st);
  ASSERT_TRUE(run.run_until([&] { return run.count<dwell_msg>() >= 8; }, 3'000'000));
  std::vector<protocol::ack_msg> start_acks;
  for (const auto& a : run.all<protocol::ack_msg>())
    if (a.seq == st) start_acks.push_back(a);
  ASSERT_EQ(start_acks.size(), 2u);
  EXPECT_EQ(start_acks[1].at_seq, start_acks[0].at_seq);
  const auto d = run.all<dwell_msg>();
  for (size_t i = 0; i < d.size(); ++i) EXPECT_EQ(d[i].cycle, i / 2) << "dwell " << i;
}

TEST(BoardCommands, ADamagedCommandGetsANakNamingIt) {
  rig r;
  const configure_msg before = r.dev.config();
  // CONFIGURE sealed (header, payload, CRC), then one payload bit flipped on the way.
  uint8_t buf[protocol::max_wire] = {};
  uint8_t* raw = buf + protocol::detail::stage;
  protocol::writer w{raw + protocol::header_bytes, protocol::max_payload};
  quick_config(64).put(w);
  ASSERT_TRUE(w.ok);
  const uint16_t seq = 77;
  const size_t raw_len =
      protocol::detail::seal_raw(static_cast<uint8_t>(protocol::msg::configure), seq, w.n, raw);
  ASSERT_GT(raw_len, 0u);
  raw[protocol::header_bytes] ^= 0x10;  // n_avg 64 -> 80
  const size_t n = protocol::detail::cobs_frame(raw_len, buf, sizeof buf);
  ASSERT_GT(n, 0u);
  r.send_cobs(buf, n);
  r.run(2000);
  const auto nak = r.last<protocol::nak_msg>();
  EXPECT_EQ(nak.seq, seq);
  EXPECT_EQ(nak.of_type, static_cast<uint8_t>(protocol::msg::configure));
  EXPECT_EQ(nak.reason, static_cast<uint8_t>(protocol::status::crc_mismatch));
  EXPECT_EQ(r.count<protocol::ack_msg>(), 0u);
  EXPECT_EQ(r.dev.config(), before);  // not executed
}

// CONFIGURE's angle table: three positions visited in order, each dwell measured where its
// index says (the model records motor 0's position at every gyro conversion); a table that is
// not the method's 180-deg pair computes no COMPENSATED.
TEST(BoardPositions, ThreePositionsAreVisitedInTableOrder) {
  rig r;
  configure_msg c = quick_config(16);
  c.flags = protocol::cfg_chop | protocol::cfg_compensate;
  c.n_positions = 3;
  c.pos_steps[1] = 50;
  c.pos_cdeg[1] = 9000;
  c.pos_steps[2] = 120;
  c.pos_cdeg[2] = 21600;
  // On-board compensation is the method's pair's alone: refused for three positions.
  r.send(c);
  r.run(400);
  EXPECT_EQ(r.last<protocol::nak_msg>().reason, static_cast<uint8_t>(protocol::status::bad_arg));
  c.flags = protocol::cfg_chop;
  configure(r, c);
  r.start();
  ASSERT_TRUE(r.run_until([&] { return r.count<dwell_msg>() >= 7; }, 3'000'000));
  const auto d = r.all<dwell_msg>();
  const int32_t at[3] = {0, 50, 120};
  size_t k = 0;
  for (size_t i = 0; i < 7; ++i) {
    EXPECT_EQ(d[i].position, i % 3);
    EXPECT_EQ(d[i].cycle, i / 3);
    ASSERT_GE(r.positions.size(), k + d[i].n);
    for (uint16_t j = 0; j < d[i].n; ++j, ++k)
      ASSERT_EQ(((r.positions[k] % 200) + 200) % 200, at[i % 3]) << "dwell " << i;
  }
  EXPECT_EQ(r.count<protocol::compensated_msg>(), 0u);
  EXPECT_EQ(r.board.motors.bad_transitions, 0u);
}

// Steps the rig one tick at a time and counts the gyro conversions that ended with motor 0's
// coils energised, until `dwells` DWELLs arrived. A conversion that ends in a tick ended with
// the coils as they stood before that tick's poll (a poll that reads the dwell's last result
// may begin the next turn at once).
struct coil_count {
  uint32_t conversions = 0, energised = 0;
};
coil_count run_counting_coils(rig& r, size_t dwells) {
  coil_count n;
  uint32_t done = r.board.adc.conversions(0);
  for (uint32_t t = 0; t < 3'000'000 && r.count<dwell_msg>() < dwells; ++t) {
    const bool energised = r.board.motors.energised(0);
    r.dev.poll();
    ++r.board.now;
    const uint32_t now_done = r.board.adc.conversions(0);
    if (now_done != done) {
      n.conversions += now_done - done;
      n.energised += energised ? now_done - done : 0;
      done = now_done;
    }
    if ((t & 255u) == 0) r.drain();
  }
  r.drain();
  return n;
}

// The holding current: off while the gyro measures (a two-phase-on hold heats the table under
// it for the whole run), on while the table turns and settles, off when stopped; CONFIGURE's
// hold flag keeps it on. The turns still land on their steps either way.
TEST(BoardCoils, OffWhileTheGyroMeasuresUnlessHeld) {
  for (const bool hold : {false, true}) {
    SCOPED_TRACE(hold ? "hold" : "release");
    rig r;
    configure_msg c = quick_config(32);
    if (hold) c.flags |= protocol::cfg_hold_coils;
    configure(r, c);
    EXPECT_EQ(r.board.motors.energised(0), hold);  // idle after CONFIGURE
    r.start();
    const coil_count n = run_counting_coils(r, 6);
    ASSERT_GE(n.conversions, 6u * 32u - 32u);
    EXPECT_EQ(n.energised, hold ? n.conversions : 0u);
    const auto d = r.all<dwell_msg>();
    for (size_t i = 0; i < d.size(); ++i) EXPECT_EQ(d[i].n, 32u);
    EXPECT_EQ(r.board.motors.bad_transitions, 0u);
    r.send(protocol::stop_msg{});
    r.run(2000);
    EXPECT_EQ(r.board.motors.energised(0), hold);
  }
}

// Homing ends only on a switch closed for home_debounce_ticks: a noise spike on its line
// elsewhere and the contact's bounce on arrival do not end it early or at the wrong step.
TEST(BoardHoming, ABouncingSwitchAndASpikeDoNotEndTheSearch) {
  rig r;
  r.board.home_at = 37;  // 163 steps back from where the table stands (200 per revolution)
  r.board.home_bounce_ticks = 400;
  r.board.home_glitch_at = r.board.now + 3000;  // ~18 steps into the search
  r.send(protocol::home_msg{});
  r.run(500);
  EXPECT_EQ(r.dev.state(), protocol::device_state::homing);
  ASSERT_TRUE(r.run_until([&] { return r.dev.state() == protocol::device_state::idle; }, 200'000));
  EXPECT_EQ(r.board.motors.position[0], 37 - 200);
  EXPECT_EQ(r.dev.motor(0).position, 0);
  EXPECT_EQ(r.count<protocol::error_msg>(), 0u);
  EXPECT_FALSE(r.board.motors.energised(0));
  // No switch at all: a revolution and a bit, then an ERROR naming the stepper.
  rig none;
  none.board.has_home = false;
  none.send(protocol::home_msg{});
  none.run(500);
  ASSERT_EQ(none.dev.state(), protocol::device_state::homing);
  ASSERT_TRUE(
      none.run_until([&] { return none.dev.state() == protocol::device_state::idle; }, 400'000));
  none.run(2000);
  const auto e = none.last<protocol::error_msg>();
  EXPECT_EQ(e.what, static_cast<uint8_t>(protocol::error_source::stepper));
  EXPECT_EQ(e.code, static_cast<uint8_t>(protocol::status::timeout));
}

// The watchdog is fed on every pass while the sequencer keeps its deadlines, and not on a pass
// that finds a deadline missed by more than stall_ticks (here: the main loop held up for 0.3 s
// in the middle of a turn); the run goes on once the sequencer has caught up.
TEST(BoardWatchdog, FedOnProgressNotUnconditionally) {
  rig r;
  configure(r, quick_config(32));
  r.start();
  const uint32_t k0 = r.board.watchdog_kicks;
  r.run(10'000);
  EXPECT_EQ(r.board.watchdog_kicks - k0, 10'000u);
  // Into a turn: the table leaves its position.
  const int32_t p0 = r.board.motors.position[0];
  ASSERT_TRUE(r.run_until([&] { return r.board.motors.position[0] != p0; }, 100'000));
  const uint32_t k1 = r.board.watchdog_kicks;
  r.board.now += fw::stall_ticks + 2000;
  r.dev.poll();
  EXPECT_FALSE(r.dev.healthy());
  EXPECT_EQ(r.board.watchdog_kicks, k1);
  const size_t dwells = r.count<dwell_msg>();
  ASSERT_TRUE(r.run_until([&] { return r.dev.healthy(); }, 10'000));
  ASSERT_TRUE(r.run_until([&] { return r.count<dwell_msg>() >= dwells + 2; }, 100'000));
}

// A dead tick crystal (the counter stops) or an oscillator fault the port reports stops the
// run: ERROR (hw_fault, clock) with the fault's bit, STATUS's clock_faults, state fault, and a
// START refused.
TEST(BoardClocks, AFailedCrystalStopsTheRunAndIsReported) {
  for (const bool frozen : {true, false}) {
    SCOPED_TRACE(frozen ? "tick counter frozen" : "XT2 fault");
    rig r;
    configure(r, quick_config(32));
    r.start();
    ASSERT_TRUE(r.run_until([&] { return r.count<dwell_msg>() >= 2; }, 1'000'000));
    if (frozen) {
      r.board.frozen_at = r.board.now;
      r.board.ticks_frozen = true;
    } else {
      r.board.clock_faults = protocol::clock_xt2;
    }
    r.run(fw::frozen_tick_polls + 1000);
    const uint8_t bit = frozen ? protocol::clock_lfxt1 : protocol::clock_xt2;
    EXPECT_EQ(r.dev.state(), protocol::device_state::fault);
    const auto e = r.last<protocol::error_msg>();
    EXPECT_EQ(e.code, static_cast<uint8_t>(protocol::status::hw_fault));
    EXPECT_EQ(e.what, static_cast<uint8_t>(protocol::error_source::clock));
    EXPECT_EQ(e.value, bit);
    const size_t dwells = r.count<dwell_msg>();
    r.board.ticks_frozen = false;
    r.board.clock_faults = 0;
    r.start();
    r.run(50'000);
    EXPECT_EQ(r.count<dwell_msg>(), dwells);
    EXPECT_EQ(r.last<protocol::nak_msg>().reason, static_cast<uint8_t>(protocol::status::hw_fault));
    r.send(protocol::stop_msg{});
    r.run(2000);
    const auto st = r.last<protocol::status_msg>();
    EXPECT_EQ(st.clock_faults, bit);
    EXPECT_EQ(st.state, static_cast<uint8_t>(protocol::device_state::fault));
  }
}

// A conversion that cannot be started (the SPI bus fails) counts as an attempt, so the dwell
// ends; it is flagged, counted in STATUS, reported once per dwell, and the run goes on.
TEST(BoardAdc, AFailedStartIsCountedFlaggedAndTheRunGoesOn) {
  rig r;
  configure(r, quick_config(32));
  r.start();
  ASSERT_TRUE(r.run_until([&] { return r.count<dwell_msg>() >= 1; }, 1'000'000));
  // Into the next dwell's conversions: the first gyro conversion of dwell 1 has started.
  const uint32_t started = r.board.adc.conversions(0);
  ASSERT_TRUE(r.run_until([&] { return r.board.adc.conversions(0) >= started + 4; }, 100'000));
  r.board.spi_fails = true;
  r.run(200);
  r.board.spi_fails = false;
  ASSERT_TRUE(r.run_until([&] { return r.count<dwell_msg>() >= 5; }, 1'000'000));
  const auto d = r.all<dwell_msg>();
  EXPECT_EQ(d[0].flags, 0);
  EXPECT_NE(d[1].flags & protocol::dwell_start_failed, 0);
  EXPECT_LT(d[1].n, 32u);
  EXPECT_GE(d[1].n, 4u);
  for (size_t i = 2; i < d.size(); ++i) {
    EXPECT_EQ(d[i].flags, 0) << "dwell " << i;
    EXPECT_EQ(d[i].n, 32u) << "dwell " << i;
  }
  EXPECT_EQ(r.dev.counters().start_failures, 32u - d[1].n);
  const auto errors = r.all<protocol::error_msg>();
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].code, static_cast<uint8_t>(protocol::status::bus_error));
  EXPECT_EQ(errors[0].what, static_cast<uint8_t>(protocol::error_source::adc));
}

// INFO says why and how often the device started and how large its history is; STATUS carries
// the stack's margin and the boot count (a reset whose INFO was lost shows in the next STATUS).
TEST(BoardInfo, ResetCauseBootCountAndStackMargin) {
  rig r;
  r.board.stack_free = 321;
  r.dev.boot({static_cast<uint8_t>(protocol::reset_cause::watchdog), 7});
  r.run(1000);
  const auto info = r.last<protocol::info_msg>();
  EXPECT_EQ(info.reset_cause, static_cast<uint8_t>(protocol::reset_cause::watchdog));
  EXPECT_EQ(info.boot_count, 7u);
  EXPECT_EQ(info.history_bytes, fw::history_bytes);
  r.send(protocol::stop_msg{});
  r.run(2000);
  const auto st = r.last<protocol::status_msg>();
  EXPECT_EQ(st.stack_free, 321u);
  EXPECT_EQ(st.boot_count, 7u);
}

// ---- issue 32: the firmware's timing and its records ----------------------------------------

// INFO is the boot's first frame, number 0, even when the boot finds the ADC missing (it was
// number 3 behind the ADC's ERRORs); the ERROR follows it.
TEST(BoardInfo, InfoIsTheBootsFirstFrameEvenWhenTheAdcFails) {
  fw::testing::code_source src;
  fw::model::host_board board{&fw::testing::code_source::call, &src};
  board.spi_fails = true;
  fw::device dev{board.hw(), fw::board_facts{}};
  dev.boot({static_cast<uint8_t>(protocol::reset_cause::power_on), 1});
  protocol::stream_decoder d{true};
  std::vector<std::pair<uint8_t, uint16_t>> got;
  for (int t = 0; t < 3000; ++t, ++board.now) {
    dev.poll();
    uint8_t buf[512];
    const size_t n = board.host_receive(buf, sizeof buf);
    for (size_t i = 0; i < n; ++i)
      if (d.push(buf[i])) got.emplace_back(d.current().type, d.current().seq);
  }
  ASSERT_GE(got.size(), 2u);
  EXPECT_EQ(got[0], std::make_pair(static_cast<uint8_t>(protocol::msg::info), uint16_t{0}));
  EXPECT_EQ(got[1].first, static_cast<uint8_t>(protocol::msg::error));
}

// A CONFIGURE is answered within the pass that reads it: the ADC's self-calibration that follows
// runs one step per pass (a blocking calibration held one pass for up to 4 conversion times per
// step, 79 ms on the F149, longer than its UART's receive queue lasts). The host port's busy
// wait advances the virtual clock, so a blocking wait shows as ticks spent inside one poll.
TEST(BoardAdc, ConfigureAndItsCalibrationNeverHoldAPass) {
  rig r;
  const auto before = r.count<protocol::ack_msg>();
  r.send(quick_config(8));
  uint32_t longest = 0;
  for (int i = 0; i < 3000; ++i) {
    const uint32_t t0 = r.board.now;
    r.dev.poll();
    longest = std::max(longest, r.board.now - t0);
    ++r.board.now;
  }
  r.drain();
  EXPECT_EQ(longest, 0u) << "a pass waited on the ADC";
  EXPECT_EQ(r.count<protocol::ack_msg>(), before + 1);
  // And the calibration did happen: zero and full scale on both channels, in that order.
  r.start();
  ASSERT_TRUE(r.run_until([&] { return r.count<dwell_msg>() >= 2; }, 200000));
  EXPECT_EQ(r.all<dwell_msg>()[0].flags, 0u);
}

// The rates a board cannot produce are refused: the MSP430F149's top rate (limits.hpp: the
// highest at which its main loop keeps up with the receive queue with margin) and a start rate
// whose interval does not fit the step timer's 16 bits.
TEST(BoardRates, ARateTheBoardCannotProduceIsRefused) {
  fw::testing::code_source src;
  fw::model::host_board board{&fw::testing::code_source::call, &src};
  fw::board_facts facts;
  facts.max_step_rate_sps = fw::msp430f149::max_step_rate_sps;
  fw::device dev{board.hw(), facts};
  dev.boot();
  protocol::stream_decoder d{true};
  const auto answer = [&](const configure_msg& c, uint16_t seq) {
    uint8_t buf[protocol::max_wire_bytes];
    board.host_send(buf, protocol::encode_wire(c, seq, buf, sizeof buf, true));
    for (int t = 0; t < 2000; ++t, ++board.now) {
      dev.poll();
      uint8_t out[512];
      const size_t n = board.host_receive(out, sizeof out);
      for (size_t i = 0; i < n; ++i)
        if (d.push(out[i]) && d.current().type != static_cast<uint8_t>(protocol::msg::info))
          return d.current().type;
    }
    return uint8_t{0};
  };
  configure_msg ok = quick_config(8);
  ok.step_rate_sps = fw::msp430f149::max_step_rate_sps;
  EXPECT_EQ(answer(ok, 1), static_cast<uint8_t>(protocol::msg::ack));
  configure_msg fast = ok;
  fast.step_rate_sps = static_cast<uint16_t>(fw::msp430f149::max_step_rate_sps + 1);
  EXPECT_EQ(answer(fast, 2), static_cast<uint8_t>(protocol::msg::nak));
  EXPECT_EQ(dev.config(), ok) << "a refused CONFIGURE left the configuration in force";
}

// The coils hold the table for the first half of the settling time and are off for the second,
// so the rotor's move to its unpowered rest is over before the first conversion (they were
// switched off 0.2 ms before it: a settle residual whose sign follows the turn's direction,
// which back-and-forth turns put into dN; docs/FIRMWARE.md).
TEST(BoardCoils, ReleasedHalfwayThroughTheSettlingTime) {
  rig r;
  configure_msg c = quick_config(8);
  c.settle_ms = 80;  // 2622 ticks
  configure(r, c);
  r.start();
  // The tick the coils went off before each dwell's first conversion.
  uint32_t off_at = 0;
  bool was_on = false;
  std::vector<uint32_t> off_before_dwell;
  uint32_t done = r.board.adc.conversions(0);
  for (uint32_t t = 0; t < 400000 && off_before_dwell.size() < 4; ++t) {
    r.dev.poll();
    ++r.board.now;
    const bool on = r.board.motors.energised(0);
    if (was_on && !on) off_at = r.board.now;
    was_on = on;
    const uint32_t n = r.board.adc.conversions(0);
    if (n != done && n % 8 == 1) off_before_dwell.push_back(r.board.now - off_at);
    done = n;
  }
  ASSERT_EQ(off_before_dwell.size(), 4u);
  for (const uint32_t d : off_before_dwell) {
    EXPECT_GE(d, 1311u + 66u) << "released less than half the settling time before the dwell";
    EXPECT_LE(d, 1311u + 66u + 10u);
  }
}

// The board's serial and the dN in force come from its non-volatile records (the F149's
// information flash) with their CRC, are reported in INFO, and the dN a host sets is written
// there (while idle) and is the one in force after a reset; a damaged record is not used.
TEST(BoardRecords, SerialAndDeltaNComeFromTheBoardsRecordsAndOutliveAReset) {
  fw::testing::code_source src;
  fw::model::host_board board{&fw::testing::code_source::call, &src};
  fw::nv::encode(fw::nv::kind_board_serial, 0x0F149123u, board.nv[fw::nv_board]);
  protocol::stream_decoder d{true};
  std::vector<protocol::info_msg> infos;
  const auto run = [&](fw::device& dev, int ticks) {
    for (int t = 0; t < ticks; ++t, ++board.now) {
      dev.poll();
      uint8_t out[512];
      const size_t n = board.host_receive(out, sizeof out);
      for (size_t i = 0; i < n; ++i)
        if (d.push(out[i]) && d.current().type == static_cast<uint8_t>(protocol::msg::info)) {
          protocol::info_msg m;
          if (d.current().as(m)) infos.push_back(m);
        }
    }
  };
  {
    fw::device dev{board.hw(), fw::board_facts{77u}};
    dev.boot();
    run(dev, 1000);
    ASSERT_EQ(infos.size(), 1u);
    EXPECT_EQ(infos[0].serial, 0x0F149123u);
    EXPECT_EQ(infos[0].stored, protocol::info_serial_stored);
    EXPECT_EQ(infos[0].delta_n_q8, 0);
    protocol::set_delta_n_msg s;
    s.delta_n_q8 = -12345;
    uint8_t buf[protocol::max_wire_bytes];
    board.host_send(buf, protocol::encode_wire(s, 5, buf, sizeof buf, true));
    run(dev, 1000);
    EXPECT_EQ(board.nv_writes, 1u);
    EXPECT_EQ(dev.delta_n_q8(), -12345);
  }
  {
    fw::device dev{board.hw(), fw::board_facts{77u}};  // the reset: a new device, the same flash
    dev.boot();
    run(dev, 1000);
    ASSERT_EQ(infos.size(), 2u);
    EXPECT_EQ(infos[1].delta_n_q8, -12345);
    EXPECT_EQ(infos[1].stored, protocol::info_serial_stored | protocol::info_delta_n_stored);
    EXPECT_EQ(dev.delta_n_q8(), -12345);
  }
  board.nv[fw::nv_board][5] ^= 0x01;    // one bit of the serial's record
  board.nv[fw::nv_delta_n][9] ^= 0x80;  // one bit of the dN record's CRC
  {
    fw::device dev{board.hw(), fw::board_facts{77u}};
    dev.boot();
    run(dev, 1000);
    ASSERT_EQ(infos.size(), 3u);
    EXPECT_EQ(infos[2].serial, 77u) << "a damaged record is not the board's serial";
    EXPECT_EQ(infos[2].stored, 0u);
    EXPECT_EQ(infos[2].delta_n_q8, 0);
  }
}

// The counters a port keeps through a reset (the F149's .noinit RAM): the next boot's INFO says
// how many frames and DWELLs the boot before sent, so a host can count what it never got.
TEST(BoardInfo, ThePreviousBootsFramesAndDwellsComeWithTheNextInfo) {
  fw::retained_counters kept;
  uint16_t sent_seq = 0;
  uint32_t sent_dwells = 0;
  {
    rig r;
    fw::boot_info b{static_cast<uint8_t>(protocol::reset_cause::power_on), 1};
    b.keep = &kept;
    r.dev.boot(b);
    r.run(1000);  // its INFO leaves first (17 ms of line)
    configure(r, quick_config(8));
    r.start();
    ASSERT_TRUE(r.run_until([&] { return r.count<dwell_msg>() >= 5; }, 400000));
    sent_dwells = static_cast<uint32_t>(r.count<dwell_msg>());
    sent_seq = static_cast<uint16_t>(r.frames.back().seq + 1);
  }
  EXPECT_EQ(kept.dwells, sent_dwells);
  EXPECT_GE(kept.next_seq, sent_seq);  // frames queued but not yet out count as sent
  rig r2;
  fw::boot_info b{static_cast<uint8_t>(protocol::reset_cause::reset_pin), 2, true, kept};
  r2.dev.boot(b);
  r2.run(1000);
  const auto info = r2.last<protocol::info_msg>();
  EXPECT_EQ(info.stored & protocol::info_prev_valid, protocol::info_prev_valid);
  EXPECT_EQ(info.prev_dwells, kept.dwells);
  EXPECT_EQ(info.prev_next_seq, kept.next_seq);
}

}  // namespace
