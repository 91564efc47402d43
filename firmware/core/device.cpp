/// \file
/// \brief The firmware core's link, commands and health (device.hpp); the sequencer is in
/// sequencer.cpp.
#include "firmware/core/device.hpp"

#include "firmware/core/nv_record.hpp"
#include "firmware/core/timebase.hpp"
#include "firmware/protocol/crc16.hpp"

namespace gyroflip::fw {

using protocol::status;

void device::boot(const boot_info& b) {
  boot_ = b;
  if (boot_.keep != nullptr) *boot_.keep = retained_counters{};
  hw_.watchdog_kick();
  load_records();
  write_port();
  const status s = adc_.reset();
  // The AD7739 after its reset: nothing is sent to it for adc_reset_wait_ms.
  const uint32_t t0 = hw_.ticks();
  const uint32_t wait = ms_to_ticks(adc_reset_wait_ms, hw_.tick_hz);
  while (hw_.ticks() - t0 < wait) hw_.busy_wait();
  if (s == status::ok) adc_.read_revision(&adc_revision_);
  apply_timing();
  last_status_ = last_ticks_ = hw_.ticks();
  // INFO is the boot's first frame (number 0); what went wrong comes after it.
  send_info();
  if (s != status::ok || adc_revision_ == 0x00 || adc_revision_ == 0xFF)
    error(status::bus_error, protocol::error_source::adc, adc_revision_);
  check_clocks(last_ticks_);
  if (state_ != protocol::device_state::fault) begin_calibration(then::idle, last_ticks_);
  transmit();
}

void device::poll() {
  // A pass does one heavy thing: a command (its answer coded and queued), or the sequencer's
  // work (a dwell's report, a turn's start), or a STATUS; the next pass does what was left, so
  // that no pass lasts longer than the UART's receive queue holds (docs/PERFORMANCE.md). The
  // sequencer is never skipped twice in a row, so a stream of commands cannot stall it.
  feed_steps();
  // After a pass that left its INFO, RESEND frame or STATUS for a long read, a short read: the
  // pass that sends it stays short, and the answers are not starved by a host that keeps sending.
  const uint16_t got = receive(tail_waited_ ? rx_light_bytes : rx_per_poll);
  if ((got & rx_commanded) != 0) handle(rx_.current());
  const bool commanded = (got & rx_commanded) != 0 && facts_.short_passes;
  const auto decoded = static_cast<uint16_t>(got & (rx_commanded - 1u));
  feed_steps();  // a command's work (a PING's INFO, a RESEND) is behind us
  const uint32_t now = hw_.ticks();
  check_clocks(now);
  bool busy = commanded;
  if (!commanded || sequencer_waited_) {
    busy = step_sequencer(now) || busy;
    sequencer_waited_ = false;
  } else {
    sequencer_waited_ = true;
  }
  feed_steps();
  // Decoding a burst of bytes is heavy too (~300 MCLK cycles a byte on the MSP430F149 with the
  // interrupts at the top of a ramp): after a long read the INFO, RESEND frame or STATUS waits a
  // pass, whose read is then a short one.
  const bool status_due = cfg_.status_period_ms != 0 && now - last_status_ >= status_ticks_;
  const bool long_read =
      facts_.short_passes && decoded > rx_light_bytes && (info_due_ || resend_due_ || status_due);
  tail_waited_ = long_read;
  const bool free = !(busy && facts_.short_passes) && !long_read;
  if (info_due_ && free) {
    // A PING's INFO, in a pass that did nothing heavy (the periodic STATUS waits a pass).
    info_due_ = false;
    send_info();
  } else if (resend_due_ && free && answer_resend(resend_per_poll)) {
    // Frames a RESEND asked for, a few a pass (the STATUS waits a pass).
  } else if (free && status_due) {
    last_status_ = now;
    send_status();
  }
  if (delta_n_dirty_ && phase_ == phase::idle) save_delta_n();
  feed_steps();
  transmit();
  // The watchdog is fed only while the sequencer keeps its deadlines: a state machine that
  // stopped acting (a lost deadline, corrupted state) resets the device instead of idling on.
  healthy_ = on_schedule(now);
  if (healthy_) hw_.watchdog_kick();
}

// The turn's step intervals are computed ahead (stepper::mover) by the main loop only: the
// queue is topped up at each stage of a pass, not once a pass, so that no stretch of the main
// loop between two top-ups is longer than what the queue holds at the top rate (8 intervals,
// 4 ms at 2 000 steps/s; docs/FIRMWARE.md, "Timing on the chip"). A full queue costs a compare.
void device::feed_steps() {
  if (phase_ == phase::turning) mover_.refill(plan_);
}

// The tick clock must move (on the MSP430F149 it is the 32 768 Hz crystal, which the chip does
// not supervise), and the port must not have seen an oscillator fault. A fault stops the run:
// its timing could not be trusted.
void device::check_clocks(uint32_t now) {
  if (now != last_ticks_) {
    last_ticks_ = now;
    polls_same_tick_ = 0;
  } else if (polls_same_tick_ < frozen_tick_polls) {
    ++polls_same_tick_;
  }
  uint8_t faults = hw_.clock_faults();
  if (polls_same_tick_ >= frozen_tick_polls) faults |= protocol::clock_lfxt1;
  const auto fresh = static_cast<uint8_t>(faults & ~clock_faults_reported_);
  if (fresh == 0) return;
  clock_faults_reported_ |= fresh;
  stat_.clock_faults = clock_faults_reported_;
  if (state_ != protocol::device_state::idle) stop_run();
  state_ = protocol::device_state::fault;
  error(status::hw_fault, protocol::error_source::clock, fresh);
}

bool device::on_schedule(uint32_t now) const {
  const auto overdue = [&](uint32_t due) {
    return static_cast<int32_t>(now - due) > static_cast<int32_t>(stall_ticks);
  };
  switch (phase_) {
    case phase::idle:
      return true;
    case phase::calibrating:
      return !cal_waiting_ || !overdue(cal_since_ + 4 * conv_ticks_ + 1);
    case phase::homing:
      return !overdue(next_home_step_);
    case phase::turning:
      // Stuck is judged by the steps made, not by how far the schedule is behind: a turn that
      // paused and resumed with a new ramp (a late main loop) is making progress.
      return !overdue(last_progress_);
    case phase::settling:
      return !overdue(phase_start_ + settle_ticks_);
    case phase::acquiring: {
      if (!shared(converting_)) return true;
      return conv_age(now) <= timeout_ticks_ + stall_ticks;
    }
  }
  return false;
}

uint16_t device::receive(uint16_t most) {
  // A bounded number per pass, so a flooded line cannot starve the sequencer, and one command
  // at most: a pass's work stays that of one command (a PING's INFO: ~12 000 MCLK cycles on the
  // MSP430F149), and the bytes behind it wait in the UART's queue for the next pass. The step
  // queue is topped up as the bytes are decoded: 64 of them take longer than it lasts at the top
  // of a 2 000-steps/s ramp on the F149. The bytes are read in place, a block at a time
  // (hal_ops::uart_read: one call per block, not per byte), and only those decoded are taken
  // from the port's queue.
  if (command_waits_) {
    command_waits_ = false;
    return rx_commanded;  // still in the decoder: no byte was pushed since it completed
  }
  const volatile uint8_t* at = nullptr;
  size_t span = 0;
  size_t used = 0;
  uint16_t i = 0;
  while (i < most) {
    if (used == span) {
      // A block of at most rx_feed_bytes: the port's queue gets its room back as the bytes are
      // decoded, not after a whole read (the queue is what a long pass has).
      span = hw_.uart_read(used, &at);
      used = 0;
      if (span == 0) return i;
      if (span > rx_feed_bytes) span = rx_feed_bytes;
    }
    const uint8_t b = at[used++];
    if (++i % rx_feed_bytes == 0) feed_steps();
    if (rx_.push(b)) {
      static_cast<void>(hw_.uart_read(used, &at));
      // A command that completes behind a long read is handled at the start of the next pass
      // (a RESEND's 16 look-ups and its GONE behind 64 decoded bytes made the F149's longest).
      if (facts_.short_passes && i > rx_light_bytes) {
        command_waits_ = true;
        return i;
      }
      return static_cast<uint16_t>(i | rx_commanded);
    }
    uint8_t type = 0;
    uint16_t seq = 0;
    status why = status::ok;
    // A damaged command gets a NAK at once (the host resends it without waiting); a damaged
    // frame of another kind (the host never sends one) is only counted.
    if (rx_.frames().take_bad_header(&type, &seq, &why) && type >= 0x20 && type <= 0x3F)
      nak_raw(type, seq, why);
  }
  if (used != 0) static_cast<void>(hw_.uart_read(used, &at));
  return i;
}

// Wire bytes to the UART while it takes them, at most tx_per_poll a pass: a UART that drains
// as fast as the bytes are coded would otherwise keep the pass here until the ring is empty.
// Coded ahead and handed over as one block (hal_ops::uart_write); the ring gives up a COBS byte
// once both its wire bytes were taken.
void device::transmit() {
  uint8_t wire[tx_per_poll];
  size_t n = 0;
  bool low = tx_low_nibble_;
  uint8_t b = 0;
  for (size_t k = 0; n < tx_per_poll && tx_.peek(k, &b); ++n) {
    wire[n] = protocol::hamming84_encode(low ? static_cast<uint8_t>(b & 0x0Fu)
                                             : static_cast<uint8_t>(b >> 4));
    if (low) ++k;
    low = !low;
  }
  if (n == 0) return;
  const size_t taken = hw_.uart_write(wire, n);
  for (size_t i = 0; i < taken; ++i) {
    if (tx_low_nibble_) tx_.pop();
    tx_low_nibble_ = !tx_low_nibble_;
  }
}

bool device::queue(uint8_t type, size_t payload_len, bool droppable) {
  // The sequence number is used even when the frame is dropped: the host then counts it
  // missing, asks for it, and hears GONE (or gets it from the history).
  uint8_t* raw = scratch_ + protocol::detail::stage;
  const size_t raw_len = protocol::detail::seal_raw(type, tx_seq_++, payload_len, raw);
  if (raw_len != 0 && protocol::kept_for_resend(type)) history_.store(raw, raw_len);
  const bool queued = queue_staged(raw_len, droppable);
  // What the next boot reports of this one (INFO prev_next_seq, prev_dwells).
  if (boot_.keep != nullptr) {
    boot_.keep->next_seq = tx_seq_;
    if (type == static_cast<uint8_t>(protocol::msg::dwell)) ++boot_.keep->dwells;
  }
  return queued;
}

// The frame staged at scratch_ + stage: COBS in place, then into the ring, whole or not at
// all, followed by the zero bytes of the line's run after it (each goes out as 2 zero wire
// bytes: line.hpp).
bool device::queue_staged(size_t raw_len, bool droppable) {
  // Room first: encoding a frame that cannot go now would only cost time (a RESEND of many). A
  // frame takes at least raw_len + 1 COBS bytes and 2 of its run after it.
  if (tx_.free() < raw_len + 1 + 2 + (droppable ? tx_reserve_bytes : 0)) {
    if (stat_.frames_dropped != 0xFFFF) ++stat_.frames_dropped;
    return false;
  }
  const size_t n = protocol::detail::cobs_frame(raw_len, scratch_, sizeof scratch_);
  const size_t cobs = n == 0 ? 0 : n - 1;  // without COBS's own 0x00
  const size_t zeros = cobs == 0 ? 0 : protocol::run_after(scratch_[cobs - 1]) / 2;
  if (cobs != 0 && tx_.free() >= cobs + zeros + (droppable ? tx_reserve_bytes : 0)) {
    static_cast<void>(tx_.push(scratch_, cobs));
    constexpr uint8_t zero = 0;
    for (size_t i = 0; i < zeros; ++i) static_cast<void>(tx_.push(&zero, 1));
    ++stat_.frames_sent;
    return true;
  }
  if (stat_.frames_dropped != 0xFFFF) ++stat_.frames_dropped;
  return false;
}

void device::ack(const protocol::frame& f) {
  remember_reply(f, true, status::ok);
  protocol::ack_msg a;
  a.seq = f.seq;
  a.of_type = f.type;
  a.at_seq = tx_seq_;  // this ACK's own number
  send(a);
}

void device::nak(const protocol::frame& f, status why) {
  remember_reply(f, false, why);
  nak_raw(f.type, f.seq, why);
}

void device::nak_raw(uint8_t type, uint16_t seq, status why) {
  protocol::nak_msg n;
  n.seq = seq;
  n.of_type = type;
  n.reason = static_cast<uint8_t>(why);
  send(n);
}

void device::error(status code, protocol::error_source what, uint32_t value) {
  protocol::error_msg e;
  e.code = static_cast<uint8_t>(code);
  e.what = static_cast<uint8_t>(what);
  e.value = value;
  stat_.last_error = e.code;
  send(e);
}

// INFO: the head, then the configuration in force written straight from cfg_ (no second copy of
// it on the stack: the F149's RAM).
void device::send_info() {
  protocol::info_head m;
  m.fw_major = fw_version_major;
  m.fw_minor = fw_version_minor;
  m.fw_patch = fw_version_patch;
  m.protocol = protocol::protocol_version;
  m.serial = serial_;
  m.mclk_hz = facts_.mclk_hz;
  m.tick_hz = hw_.tick_hz;
  m.adc_revision = adc_revision_;
  m.max_n_avg = protocol::max_n_avg;
  m.max_raw_codes = protocol::raw_msg::max_codes;
  m.range = ad7739::range_bipolar_2v5;
  m.reset_cause = boot_.reset_cause;
  m.boot_count = boot_.boot_count;
  m.history_bytes = static_cast<uint16_t>(history_bytes);
  m.board = static_cast<uint8_t>(facts_.board);
  m.stored = stored_;
  m.delta_n_q8 = delta_n_q8_;
  m.prev_next_seq = boot_.prev.next_seq;
  m.prev_dwells = boot_.prev.dwells;
  protocol::writer w{scratch_ + protocol::detail::stage + protocol::header_bytes, max_sent_payload};
  m.put_head(w);
  cfg_.put(w);
  if (w.ok) queue(static_cast<uint8_t>(protocol::msg::info), w.n, false);
}

void device::send_status() {
  stat_.state = static_cast<uint8_t>(state_);
  stat_.uptime_ticks = hw_.ticks();
  const auto& c = rx_.counts();
  stat_.rx_frames_ok = static_cast<uint16_t>(c.good);
  stat_.rx_errors = static_cast<uint16_t>(c.bad());
  stat_.line_corrected = static_cast<uint16_t>(rx_.line().corrected);
  stat_.line_uncorrectable = static_cast<uint16_t>(rx_.line().uncorrectable);
  stat_.history_oldest = history_.empty() ? tx_seq_ : history_.oldest_seq();
  stat_.stack_free = hw_.stack_free();
  stat_.boot_count = boot_.boot_count;
  send(stat_);
}

// RESEND: each frame still in the history is marked there, and goes out again with its own
// sequence number (answer_resend: on a port with short passes resend_per_poll a pass, from the
// next pass on, so that the loop keeps draining the receive queue and feeding the steps); the
// others are named in one GONE, at once. A marked frame waits while the ring has no room for it
// and the live frames' reserve; a RESEND while marked frames wait adds its own.
void device::resend(const protocol::frame& f) {
  protocol::resend_msg m;
  if (!f.as(m)) return nak(f, status::bad_frame);
  // The numbers no longer held, as a mask over m.seqs (not a second message on the stack: the
  // F149's RAM); GONE is written from it (gone_msg's layout: u8 count, u16 each).
  uint16_t gone = 0;
  uint8_t n_gone = 0;
  for (uint8_t i = 0; i < m.count; ++i) {
    // A number not yet sent (a host probing past what it heard): nothing to say about it.
    if (static_cast<int16_t>(static_cast<uint16_t>(m.seqs[i] - tx_seq_)) >= 0) continue;
    // Each look-up walks the history: the step queue is topped up between them (16 walks and the
    // GONE outlast it at the top of a 2 000-steps/s ramp on the F149).
    if ((i & 3u) == 3u) feed_steps();
    if (history_.mark(m.seqs[i])) {
      resend_due_ = true;
    } else {
      gone = static_cast<uint16_t>(gone | (1u << i));
      ++n_gone;
    }
  }
  if (!facts_.short_passes) answer_resend(static_cast<int>(m.count));
  if (n_gone == 0) return;
  feed_steps();
  protocol::writer w{scratch_ + protocol::detail::stage + protocol::header_bytes, max_sent_payload};
  w.u8(n_gone);
  for (uint8_t i = 0; i < m.count; ++i)
    if ((gone & (1u << i)) != 0) w.u16(m.seqs[i]);
  if (w.ok) queue(static_cast<uint8_t>(protocol::msg::gone), w.n, false);
}

bool device::answer_resend(int n) {
  bool sent = false;
  for (int k = 0; k < n && resend_due_; ++k) {
    const size_t len = history_.marked();
    if (len == 0) {
      resend_due_ = false;
      break;
    }
    // The frame's COBS bytes (at most len + 1 here) and its run (at most 5 ring bytes), with the
    // reserve the live DWELL, COMPENSATED and STATUS keep: a resent frame yields to them.
    if (tx_.free() < len + 1 + 5 + tx_reserve_bytes) break;
    uint8_t* raw = scratch_ + protocol::detail::stage;
    if (history_.take_marked(raw, sizeof scratch_ - protocol::detail::stage - 1) == len &&
        queue_staged(len, false) && stat_.retransmits != 0xFFFF)
      ++stat_.retransmits;
    sent = true;
    feed_steps();
  }
  return sent;
}

bool device::repeated_command(const protocol::frame& f) {
  const uint16_t crc = protocol::crc16(f.payload, f.length);
  if (!have_last_cmd_ || f.seq != last_cmd_seq_ || f.type != last_cmd_type_ || crc != last_cmd_crc_)
    return false;
  // The same command again (its ACK or NAK was lost): the same answer, nothing executed.
  if (last_cmd_acked_) {
    protocol::ack_msg a;
    a.seq = f.seq;
    a.of_type = f.type;
    a.at_seq = last_cmd_at_seq_;
    send(a);
  } else {
    nak_raw(f.type, f.seq, last_cmd_why_);
  }
  return true;
}

void device::remember_reply(const protocol::frame& f, bool acked, status why) {
  if (f.type == static_cast<uint8_t>(protocol::msg::ping)) return;  // answered every time
  have_last_cmd_ = true;
  last_cmd_seq_ = f.seq;
  last_cmd_type_ = f.type;
  last_cmd_crc_ = protocol::crc16(f.payload, f.length);
  last_cmd_acked_ = acked;
  last_cmd_at_seq_ = tx_seq_;  // the reply about to be sent takes this number
  last_cmd_why_ = why;
}

bool device::method_pair() const {
  return protocol::is_method_pair(cfg_);
}

// CONFIGURE: its own function, so that handle()'s frame does not hold a configuration on the
// stack under every other command's path (the F149's RAM).
// CONFIGURE decodes straight into cfg_, the configuration in force kept meanwhile in the frame
// scratch as its CONFIGURE payload and put back when the new one is refused (a second
// configuration on the stack would not fit the F149's RAM).
void device::configure(const protocol::frame& f) {
  const bool idle = state_ == protocol::device_state::idle;
  const bool fault = state_ == protocol::device_state::fault;
  if (f.length != protocol::configure_payload) return nak(f, status::bad_frame);
  if (!idle) return nak(f, fault ? status::hw_fault : status::busy);
  protocol::writer saved{scratch_, sizeof scratch_};
  cfg_.put(saved);
  status s = f.as(cfg_) ? protocol::check_configure(cfg_, facts_.mclk_hz) : status::bad_frame;
  // What this board can produce: its top step rate, and a start rate whose interval fits the
  // step timer's 16 bits.
  if (s == status::ok && (cfg_.step_rate_sps > facts_.max_step_rate_sps ||
                          hw_.tick_hz / cfg_.start_rate_sps > 0xFFFFu))
    s = status::bad_arg;
  if (s != status::ok) {
    protocol::reader back{scratch_, saved.n};
    cfg_.get(back);
    return nak(f, s);
  }
  configured_ = true;  // START needs a configuration of this boot (docs/PROTOCOL.md)
  timing_stale_ = true;
  set_coils(false);
  begin_calibration(then::idle, hw_.ticks());
  return ack(f);
}

void device::handle(const protocol::frame& f) {
  const auto type = static_cast<protocol::msg>(f.type);
  // PING and RESEND change nothing: answered every time. Every other command runs once.
  if (type == protocol::msg::resend) return resend(f);
  if (type != protocol::msg::ping && repeated_command(f)) return;
  const bool idle = state_ == protocol::device_state::idle;
  const bool fault = state_ == protocol::device_state::fault;
  switch (type) {
    case protocol::msg::ping: {
      protocol::ping_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      ack(f);
      // On a port with short passes the INFO (92 bytes, the longest frame a command answers)
      // goes out in the next pass: the ACK's and the INFO's coding in one pass was the longest
      // main-loop pass of the F149 (31 000 cycles, 5.7 ms with the interrupts meanwhile).
      if (facts_.short_passes) {
        info_due_ = true;
        return;
      }
      return send_info();
    }
    case protocol::msg::configure:
      return configure(f);
    case protocol::msg::start: {
      protocol::start_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      if (fault) return nak(f, status::hw_fault);
      // Only a configuration a host sent since this boot: a rebooted device does not know where
      // its table stands, and a START retried from before the reset (its first ACK lost) would
      // start the boot's default configuration unhomed. A host's CONFIGURE either homes first
      // (cfg_home) or is the host saying the table stands at position 0 (docs/PROTOCOL.md).
      if (!configured_ || m.config_crc != protocol::configure_crc(cfg_))
        return nak(f, status::config_mismatch);
      if (idle) start_run(false);
      return ack(f);
    }
    case protocol::msg::stop: {
      protocol::stop_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      if (!fault) stop_run();
      // A dN set during the run goes to the information flash now, before the answer (the host
      // waits for it, so nothing arrives while the flash holds the CPU).
      if (delta_n_dirty_) save_delta_n();
      ack(f);
      return send_status();
    }
    case protocol::msg::home: {
      protocol::home_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      if (!idle) return nak(f, fault ? status::hw_fault : status::busy);
      home_then_run_ = false;
      state_ = protocol::device_state::homing;
      phase_ = phase::homing;
      converting_ = false;
      home_steps_ = 0;
      home_closed_ = false;
      next_home_step_ = hw_.ticks();
      set_coils(true);
      return ack(f);
    }
    case protocol::msg::set_delta_n: {
      protocol::set_delta_n_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      if (m.delta_n_q8 != delta_n_q8_) delta_n_dirty_ = true;
      delta_n_q8_ = m.delta_n_q8;
      // Idle: saved before the ACK (the host waits for it: nothing arrives while the flash holds
      // the CPU). Running: at the run's end.
      if (delta_n_dirty_ && idle && phase_ == phase::idle) save_delta_n();
      return ack(f);
    }
    case protocol::msg::calibrate: {
      protocol::calibrate_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      if (m.cycles < 2 || !method_pair()) return nak(f, status::bad_arg);
      if (fault) return nak(f, status::hw_fault);
      if (state_ == protocol::device_state::homing) return nak(f, status::busy);
      cal_.begin(m.cycles);
      cal_wait_a_ = true;
      if (idle) start_run(true);
      return ack(f);
    }
    default:
      return nak(f, status::not_supported);
  }
}

void device::load_records() {
  uint8_t rec[nv::record_bytes];
  uint32_t v = 0;
  serial_ = facts_.serial;
  stored_ = boot_.prev_valid ? protocol::info_prev_valid : 0;
  if (hw_.nv_read(nv_board, rec, sizeof rec) && nv::decode(rec, nv::kind_board_serial, &v)) {
    serial_ = v;
    stored_ |= protocol::info_serial_stored;
  }
  if (hw_.nv_read(nv_delta_n, rec, sizeof rec) && nv::decode(rec, nv::kind_delta_n, &v)) {
    delta_n_q8_ = static_cast<int32_t>(v);
    stored_ |= protocol::info_delta_n_stored;
  }
}

// The dN in force to the information flash (the MSP430F149 holds the CPU for ~15 ms while it
// erases and writes the segment: only while idle, and never while the host may be sending).
void device::save_delta_n() {
  delta_n_dirty_ = false;
  uint8_t rec[nv::record_bytes];
  nv::encode(nv::kind_delta_n, static_cast<uint32_t>(delta_n_q8_), rec);
  if (!hw_.nv_write(nv_delta_n, rec, sizeof rec)) return;
  uint8_t back[nv::record_bytes];
  uint32_t v = 0;
  if (!hw_.nv_read(nv_delta_n, back, sizeof back) || !nv::decode(back, nv::kind_delta_n, &v) ||
      static_cast<int32_t>(v) != delta_n_q8_)
    error(status::hw_fault, protocol::error_source::configuration, nv_delta_n);
}

}  // namespace gyroflip::fw
