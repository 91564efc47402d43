// The board facts of issue 20 on the host port (docs/HARDWARE.md, FIRMWARE.md, PROTOCOL.md):
// RESEND and GONE, commands executed once, NAK for a damaged command, the angle table, the
// coils' holding current, homing through bounce and noise, the watchdog fed on progress, clock
// faults, failed conversion starts, and what INFO and STATUS say about the board.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "firmware/harness.hpp"

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

}  // namespace
