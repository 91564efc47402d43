/// \file
/// \brief The sequencer and sampler of the firmware core (device.hpp): calibrate the ADC ->
/// [home] -> turn -> settle -> acquire n_avg gyro and n_temp temperature conversions -> report
/// -> turn to the next position of the angle table. Every wait is a state checked against the
/// tick counter, so commands are served between any two conversions; the steps and the
/// conversions' restart run in the port's interrupts where it has them (on_step_timer, on_rdy),
/// so a long main-loop pass delays neither (docs/FIRMWARE.md, "Timing on the chip").
#include "firmware/core/device.hpp"
#include "firmware/core/timebase.hpp"
#include "firmware/util/intmath.hpp"

namespace gyroflip::fw {

using protocol::status;

namespace {
// What on_rdy hands the main loop (device::adc_result::kind).
constexpr uint8_t res_value = 0;         // a result of this conversion
constexpr uint8_t res_stale = 1;         // a result that was not this conversion's (refused)
constexpr uint8_t res_read_failed = 2;   // the SPI read failed: the conversion is lost
constexpr uint8_t res_start_failed = 3;  // the next conversion could not be started (SPI)

// A critical section on ports whose interrupts call into the core (hal_ops::critical).
class locked {
 public:
  explicit locked(const hal& hw) : hw_(hw) { hw_.critical(true); }
  ~locked() { hw_.critical(false); }
  locked(const locked&) = delete;
  locked& operator=(const locked&) = delete;

 private:
  const hal& hw_;
};
}  // namespace

void device::write_port() {
  hw_.stepper_port(stepper::port_byte(motors_[0], motors_[1]));
}

// The coils of the flip motor (and of the other one when it turns with it) are on while the
// table turns and settles, and off during dwells and while idle: a two-phase-on hold is ~2 x
// the coil's I^2 R of heat in the table under the gyro for the whole run (docs/HARDWARE.md).
// The motor keeps its phase, so the next turn starts from where the rotor stands.
// cfg_hold_coils keeps them on; other_motor "hold" keeps the other motor on whatever happens.
void device::set_coils(bool on) {
  const bool hold = (cfg_.flags & protocol::cfg_hold_coils) != 0;
  stepper::motor& flip = motors_[cfg_.flip_motor & 1];
  stepper::motor& other = motors_[1 - (cfg_.flip_motor & 1)];
  flip.energised = on || hold;
  switch (static_cast<protocol::other_motor>(cfg_.other_motor)) {
    case protocol::other_motor::off:
      other.energised = false;
      break;
    case protocol::other_motor::hold:
      other.energised = true;
      break;
    default:
      other.energised = on || hold;
      break;
  }
  write_port();
}

// The configuration's times in ticks and its ramp, once per CONFIGURE (64-bit arithmetic: never
// per poll).
void device::apply_timing() {
  const bool chop = (cfg_.flags & protocol::cfg_chop) != 0;
  conv_ticks_ =
      mclk_to_ticks(ad7739::conversion_mclk(chop, cfg_.filter_word), hw_.tick_hz, facts_.mclk_hz);
  settle_ticks_ = ms_to_ticks(cfg_.settle_ms, hw_.tick_hz);
  status_ticks_ = ms_to_ticks(cfg_.status_period_ms, hw_.tick_hz);
  // Three conversion times (issue 8), plus one tick for the quantisation of the start time.
  timeout_ticks_ = 3 * conv_ticks_ + 1;
  plan_ =
      stepper::make_plan({cfg_.start_rate_sps, cfg_.step_rate_sps, cfg_.ramp_sps2}, hw_.tick_hz);
  home_interval_ = stepper::interval(
      stepper::make_plan({cfg_.start_rate_sps, cfg_.start_rate_sps, 1}, hw_.tick_hz), 0, 1);
}

// The ADC's channels are set up and self-calibrated (zero scale, then full scale: the data
// sheet's order) one step per poll: a calibration waits for /RDY up to 4 conversion times per
// step without holding the main loop (a blocking wait took up to 79 ms, longer than the UART's
// receive queue lasts).
void device::begin_calibration(then next, uint32_t now) {
  after_cal_ = next;
  cal_step_ = 0;
  cal_waiting_ = false;
  cal_since_ = now;
  converting_ = false;
  phase_ = phase::calibrating;
}

void device::step_calibration(uint32_t now) {
  if (timing_stale_) {  // a new configuration's times: a pass of their own (CONFIGURE's was full)
    timing_stale_ = false;
    apply_timing();
    return;
  }
  if (cal_step_ < 4) {
    const uint8_t ch = (cal_step_ & 2u) == 0 ? cfg_.gyro_channel : cfg_.temp_channel;
    if (cal_waiting_) {
      const bool ready = adc_.ready();
      const bool late = now - cal_since_ > 4 * conv_ticks_ + 1;
      if (!ready && !late) return;
      cal_waiting_ = false;
      if (!ready) {
        error(status::timeout, protocol::error_source::adc, ch);
        cal_step_ = static_cast<uint8_t>((cal_step_ | 1u) + 1u);  // on to the next channel
      } else {
        ++cal_step_;
      }
      return;
    }
    status s = status::ok;
    if ((cal_step_ & 1u) == 0) {
      const bool chop = (cfg_.flags & protocol::cfg_chop) != 0;
      s = adc_.setup_channel(ch, ad7739::range_bipolar_2v5);
      if (s == status::ok) s = adc_.set_conversion_time(ch, chop, cfg_.filter_word);
    }
    if (s == status::ok) s = adc_.start_calibration(ch, (cal_step_ & 1u) != 0);
    if (s != status::ok) {
      error(s, protocol::error_source::adc, ch);
      cal_step_ = static_cast<uint8_t>((cal_step_ | 1u) + 1u);
      return;
    }
    cal_waiting_ = true;
    cal_since_ = now;
    return;
  }
  if (after_cal_ == then::run) return begin_run(now);
  phase_ = phase::idle;
}

void device::start_run(bool by_calibrate) {
  stat_.cycle = 0;
  position_ = 0;
  gyro_index_ = 0;
  stop_after_cal_ = by_calibrate;
  state_ = protocol::device_state::running;
  set_coils(false);
  begin_calibration(then::run, hw_.ticks());
}

// After the calibration: home first when the configuration says so, then the first turn.
void device::begin_run(uint32_t now) {
  if ((cfg_.flags & protocol::cfg_home) != 0) {
    home_then_run_ = true;
    home_steps_ = 0;
    home_closed_ = false;
    next_home_step_ = now;
    phase_ = phase::homing;
    set_coils(true);
  } else {
    begin_turn(0, now);
  }
}

void device::stop_run() {
  {
    // The step timer and the /RDY interrupt stop acting before the coils go off.
    const locked guard(hw_);
    phase_ = phase::idle;
    converting_ = false;
    turn_due_ = false;
    if (step_irq_armed_) hw_.step_timer(false, 0);
    step_irq_armed_ = false;
  }
  state_ = protocol::device_state::idle;
  cal_.cancel();
  set_coils(false);
}

void device::begin_turn(uint8_t to_position, uint32_t now) {
  const stepper::motor& flip = motors_[cfg_.flip_motor & 1];
  const int32_t steps = protocol::turn_steps(cfg_, flip.position, to_position);
  phase_start_ = now;
  coils_released_ = false;
  set_coils(true);
  if (steps == 0) {
    phase_ = phase::settling;
    return;
  }
  // The first step is due at a tick read after the first intervals are computed, not at the
  // pass's: a pass that reported a dwell first may be well past its start, and the first
  // interval would come short.
  mover_.begin(steps, now, plan_, 2);
  // With a step timer, the first step is due a few ticks ahead, at the compare like every other
  // step: due at once, it came as late as any interrupt between this read and the arming below
  // made it, and the first interval was short by that much (3 ticks on the F149's simulator).
  const uint32_t first = hw_.ticks() + (hw_.has_step_timer() ? first_step_lead_ticks : 0u);
  mover_.retime(first);
  seen_steps_ = 0;
  last_progress_ = first;
  phase_ = phase::turning;
  // A port with a step timer takes the steps in its interrupt from here on.
  if (hw_.has_step_timer()) {
    step_irq_armed_ = true;
    hw_.step_timer(true, first);
  }
}

// The step timer's interrupt (or poll() on a port without one).
bool device::on_step_timer(uint32_t now, uint32_t* next_due) {
  if (shared(phase_) != phase::turning) return false;
  stepper::motor& flip = motors_[cfg_.flip_motor & 1];
  stepper::motor& other = motors_[1 - (cfg_.flip_motor & 1)];
  const bool more = mover_.take_step(flip, other, static_cast<stepper::follower>(cfg_.other_motor),
                                     now, next_due);
  write_port();
  return more;
}

void device::step_turn(uint32_t now) {
  // The queue is topped up whole (device::feed_steps does it at each stage of a pass too): two
  // a pass fell behind the top of a ramp at 2 000 steps/s on the board, where a pass with
  // transmit's 16 bytes lasts longer than two intervals (tests/firmware/test_msp430_sim.cpp).
  mover_.refill(plan_);
  const uint16_t done = mover_.steps_done();
  if (done != seen_steps_) {
    seen_steps_ = done;
    last_progress_ = now;
  }
  if (!mover_.busy()) {
    // The last step is taken: the settling begins (with the coils on: they hold the table
    // against the turn's ring-down).
    step_irq_armed_ = false;
    phase_ = phase::settling;
    phase_start_ = now;
    return;
  }
  if (mover_.paused()) {
    // The main loop fell behind the steps: the move waited, and goes on with a new ramp from
    // standstill (never a burst of late steps, never a top-rate step after a pause).
    mover_.rebase(now, plan_);
    if (step_irq_armed_) hw_.step_timer(true, now);
    return;
  }
  if (!step_irq_armed_ && static_cast<int32_t>(now - mover_.next_due()) >= 0) {
    uint32_t next = 0;
    static_cast<void>(on_step_timer(now, &next));
  }
}

void device::begin_dwell(uint32_t now) {
  dwell_ = protocol::dwell_msg{};
  dwell_.cycle = stat_.cycle;
  dwell_.position = position_;
  dwell_.t_start_ticks = now;
  if (step_fault_) dwell_.flags |= protocol::dwell_step_fault;
  step_fault_ = false;
  attempts_ = 0;
  started_ = 0;
  planned_ = static_cast<uint16_t>(cfg_.n_avg + cfg_.n_temp);
  res_head_ = res_tail_ = 0;
  converting_ = false;
  fault_reported_ = false;
  raw_.count = 0;
  if (position_ == 0) cal_wait_a_ = false;
  set_coils(false);  // settled: no holding current under the gyro while it measures
  // Periods captured during the turn are not this dwell's tilt.
  pwm_period p;
  for (uint8_t axis = 0; axis < 2; ++axis)
    while (hw_.pwm_capture(axis, &p)) {
    }
  phase_ = phase::acquiring;
  start_conversion(now);
}

// Homing: one step at the start rate until the switch has read closed for home_debounce_ticks
// without a break (a bouncing contact or a noise spike on its line does not end the search),
// or a revolution and a bit found nothing. The table stands still while the switch reads closed
// and for home_debounce_ticks after (a bounce's open half must not move it off home).
void device::step_homing(uint32_t now) {
  stepper::motor& flip = motors_[cfg_.flip_motor & 1];
  const bool closed = hw_.home_switch();
  if (closed && !home_closed_) home_closed_since_ = now;
  home_closed_ = closed;
  const bool found = closed && now - home_closed_since_ >= home_debounce_ticks;
  const bool gave_up = !closed && home_steps_ > cfg_.steps_per_rev;
  if (found || gave_up) {
    if (gave_up) {
      error(status::timeout, protocol::error_source::stepper, home_steps_);
      step_fault_ = true;
    }
    flip.position = 0;
    if (home_then_run_) {
      state_ = protocol::device_state::running;
      begin_turn(0, now);
    } else {
      phase_ = phase::idle;
      state_ = protocol::device_state::idle;
      set_coils(false);
    }
    return;
  }
  // Hold still while a closed switch settles; step on while it is open. A late poll takes one
  // step and times the next from now (no burst).
  if (!closed && static_cast<int32_t>(now - next_home_step_) >= 0) {
    flip.step(-1);
    write_port();
    ++home_steps_;
    const bool late = now - next_home_step_ >= home_interval_;
    next_home_step_ = (late ? now : next_home_step_) + home_interval_;
  }
  // After any closed reading the next step waits a whole debounce time: a contact bouncing on
  // arrival reads open half the time, and stepping on then would leave the home step.
  if (closed) next_home_step_ = now + home_debounce_ticks;
}

bool device::step_sequencer(uint32_t now) {
  switch (phase_) {
    case phase::idle:
      return false;
    case phase::calibrating:
      step_calibration(now);
      return false;
    case phase::homing:
      step_homing(now);
      return false;
    case phase::turning:
      step_turn(now);
      return false;
    case phase::settling: {
      // The coils hold the table for the first half of the settling time and are released for
      // the second half, so that the rotor's move to its unpowered rest (the release transient)
      // is over before the first conversion (docs/FIRMWARE.md, "The settle residual").
      const uint32_t held = now - phase_start_;
      if (!coils_released_ && 2 * held >= settle_ticks_) {
        coils_released_ = true;
        set_coils(false);
      }
      if (held < settle_ticks_) return false;
      begin_dwell(now);
      return true;
    }
    case phase::acquiring:
      if (turn_due_) {
        turn_due_ = false;
        begin_turn(position_, now);
        return true;
      }
      return step_acquisition(now);
  }
  return false;
}

void device::capture_pwm() {
  pwm_period p;
  while (hw_.pwm_capture(0, &p)) {
    dwell_.ax_high_ticks += p.high_ticks;
    dwell_.ax_period_ticks += p.period_ticks;
  }
  while (hw_.pwm_capture(1, &p)) {
    dwell_.ay_high_ticks += p.high_ticks;
    dwell_.ay_period_ticks += p.period_ticks;
  }
}

// Ticks since the running conversion started, at `now`; 0 when it started after `now` (the /RDY
// interrupt started it while this pass ran, after the pass read the tick counter).
uint16_t device::conv_age(uint32_t now) const {
  const auto d = static_cast<int16_t>(static_cast<uint16_t>(now) - shared(conv_start_));
  return d < 0 ? uint16_t{0} : static_cast<uint16_t>(d);
}

uint8_t device::channel_of(uint16_t attempt) const {
  return attempt < cfg_.n_avg ? cfg_.gyro_channel : cfg_.temp_channel;
}

// Starts conversion number started_ of the dwell (the caller holds off on_rdy: the main loop in
// a critical section, or on_rdy itself). False when the SPI bus failed: the attempt is counted
// (a dead ADC must not hold the dwell forever) and the caller queues res_start_failed after
// what it queues first.
bool device::start_next(uint32_t now) {
  const uint8_t ch = channel_of(started_);
  ++started_;
  if (adc_.start_single(ch) != status::ok) return false;
  conv_start_ = static_cast<uint16_t>(now);
  converting_ = true;
  return true;
}

// One result for the main loop (on_rdy's side of the queue, or the main loop's in a critical
// section).
void device::push_result(uint8_t kind, int32_t code, uint8_t st) {
  const uint8_t flags =
      static_cast<uint8_t>((kind << 6) | (st & (ad7739::chst_noref | ad7739::chst_ovr)));
  results_[res_tail_ % adc_queue_len] =
      (static_cast<uint32_t>(code) & 0xFFFFFFu) | (static_cast<uint32_t>(flags) << 24);
  barrier();
  share(res_tail_, static_cast<uint8_t>(res_tail_ + 1u));
}

// The main loop starts a conversion: the dwell's first, or the next when on_rdy could not (its
// queue was full, or the port has no /RDY interrupt), or after a timeout.
void device::start_conversion(uint32_t now) {
  const locked guard(hw_);
  if (converting_ || started_ >= planned_) return;
  if (static_cast<uint8_t>(res_tail_ - res_head_) > adc_queue_len - 2) return;
  // A result nobody read (a RDY that came after its timeout) holds /RDY low through the next
  // mode write: read it away first, so that the wait is for the new conversion.
  if (adc_.ready()) {
    int32_t old = 0;
    uint8_t st = 0;
    static_cast<void>(adc_.read_result(cfg_.gyro_channel, &old, &st));
    static_cast<void>(adc_.read_result(cfg_.temp_channel, &old, &st));
  }
  if (!start_next(now)) push_result(res_start_failed, 0, 0);
}

// /RDY fell (the port's interrupt, or poll() on a port without one). When this conversion's time
// has passed, the dwell's next conversion is started first and this one's result read after:
// the AD7739 keeps a channel's result until its next conversion's scaling time, a conversion
// time away, so the ADC restarts within a mode write of /RDY (~200 MCLK cycles) instead of
// after the read and its checks (~1 000 on the MSP430F149). The result is taken if the dump-mode
// status byte names this channel with its RDY bit set and the conversion time has passed: a
// result earlier than that is an older one (the AD7739 drives /RDY high only in the scaling time
// at the end of the new conversion, data sheet Rev. A). A refused result is reported and the
// wait goes on. Two places in the queue to the main loop are kept for this result and a failed
// start; a result that finds the queue full is left for the main loop (step_acquisition).
void device::on_rdy(uint32_t now) {
  if (!converting_) return;
  const auto used = static_cast<uint8_t>(res_tail_ - shared(res_head_));
  if (used + 2u > adc_queue_len) return;
  const uint8_t ch = channel_of(static_cast<uint16_t>(started_ - 1u));
  const bool in_time = conv_age(now) + 1u >= conv_ticks_;
  bool restarted = false;
  bool start_failed = false;
  if (in_time && started_ < planned_) {
    restarted = start_next(now);
    start_failed = !restarted;
  }
  int32_t code = 0;
  uint8_t st = 0;
  uint8_t kind = res_read_failed;
  if (adc_.read_result(ch, &code, &st) == status::ok) {
    const bool mine = (st >> ad7739::chst_channel_shift) == ch && (st & ad7739::chst_rdy) != 0;
    kind = mine && in_time ? res_value : res_stale;
  }
  // A refused result after the next conversion started: this one is lost, not awaited.
  if (kind == res_stale && (restarted || start_failed)) kind = res_read_failed;
  if (!restarted) converting_ = kind == res_stale;
  push_result(kind, code, st);
  if (start_failed) push_result(res_start_failed, 0, 0);
}

// A conversion that ended without a code: counted as an attempt, flagged, reported once per
// dwell; a gyro conversion ends the RAW block (blocks hold consecutive conversions) and its index
// is skipped.
void device::missing(uint8_t flag) {
  const bool gyro = attempts_ < cfg_.n_avg;
  ++attempts_;
  dwell_.flags |= flag;
  if (flag == protocol::dwell_rdy_timeout) {
    if (stat_.rdy_timeouts != 0xFFFF) ++stat_.rdy_timeouts;
  } else if (stat_.start_failures != 0xFFFF) {
    ++stat_.start_failures;
  }
  if (gyro) {
    flush_raw();
    ++gyro_index_;
  }
  if (!fault_reported_) {
    fault_reported_ = true;
    error(flag == protocol::dwell_rdy_timeout ? status::timeout : status::bus_error,
          protocol::error_source::adc, gyro_index_);
  }
}

void device::account(uint32_t result) {
  const auto kind = static_cast<uint8_t>(result >> 30);
  const auto st = static_cast<uint8_t>(result >> 24);
  // The 24-bit code, sign-extended.
  const int32_t code = static_cast<int32_t>((result & 0xFFFFFFu) ^ 0x800000u) - 0x800000;
  if (kind == res_stale) {
    dwell_.flags |= protocol::dwell_stale;
    if (stat_.stale_results != 0xFFFF) ++stat_.stale_results;
    return;
  }
  if (kind != res_value) return missing(protocol::dwell_start_failed);
  const bool gyro = attempts_ < cfg_.n_avg;
  ++attempts_;
  if ((st & ad7739::chst_noref) != 0) dwell_.flags |= protocol::dwell_noref;
  if (!gyro) {
    dwell_.temp_sum += code;
    ++dwell_.n_temp;
    return;
  }
  if (dwell_.n == 0 || code < dwell_.code_min) dwell_.code_min = code;
  if (dwell_.n == 0 || code > dwell_.code_max) dwell_.code_max = code;
  if (code <= -ad7739::code_zero || code >= ad7739::code_zero - 1 || (st & ad7739::chst_ovr) != 0)
    dwell_.flags |= protocol::dwell_adc_clip;
  dwell_.code_sum += code;
  ++dwell_.n;
  if ((cfg_.flags & protocol::cfg_raw) != 0) {
    if (raw_.count == 0) raw_.first_index = gyro_index_;
    raw_.set(raw_.count++, code);
    if (raw_.count == protocol::raw_msg::max_codes) flush_raw();
  }
  ++gyro_index_;
}

bool device::step_acquisition(uint32_t now) {
  capture_pwm();
  // A result /RDY's interrupt left unread (its queue was full, or the port has no interrupt):
  // taken here, in a critical section on a port whose interrupt reads results too. Before the
  // conversion time a low /RDY is an older result: left to the read-away of the next start.
  if (shared(converting_) && conv_age(now) + 1u >= conv_ticks_ && adc_.ready()) {
    const locked guard(hw_);
    on_rdy(now);
  }
  // What on_rdy handed over, in the order of the conversions.
  while (res_head_ != shared(res_tail_)) {
    barrier();
    const uint32_t r = results_[res_head_ % adc_queue_len];
    share(res_head_, static_cast<uint8_t>(res_head_ + 1u));
    const uint16_t before = attempts_;
    account(r);
    if (before < cfg_.n_avg && attempts_ == cfg_.n_avg) flush_raw();
  }
  if (shared(converting_)) {
    if (conv_age(now) > timeout_ticks_) {
      bool timed_out = false;
      {
        const locked guard(hw_);
        // on_rdy may have taken the result meanwhile.
        if (converting_ &&
            static_cast<uint16_t>(static_cast<uint16_t>(now) - conv_start_) > timeout_ticks_) {
          converting_ = false;
          timed_out = true;
        }
      }
      // RDY never came: count it, report the first of this dwell, and go on with the next one.
      if (timed_out) missing(protocol::dwell_rdy_timeout);
    }
  }
  if (attempts_ >= planned_ && !shared(converting_)) {
    flush_raw();
    finish_dwell(now);
    return true;
  }
  if (!shared(converting_)) start_conversion(now);
  return false;
}

void device::flush_raw() {
  if (raw_.count == 0) return;
  if (!send(raw_, true)) dwell_.flags |= protocol::dwell_raw_dropped;
  raw_.count = 0;
}

// The method's pair (positions 0 and 1, 180 deg apart): r = (y_0 - y_1) / 2 and c = (y_0 + y_1)
// / 2 after each position-1 dwell (paper eqn 7), COMPENSATED r - dN (eqn 12), and the
// calibration of dN (eqns 8-11).
void device::process_pair(const protocol::dwell_msg& d) {
  const bool have = d.n != 0;
  const int32_t mean = have ? mean_q8(d.code_sum, d.n) : 0;
  if (d.position == 0) {
    mean_a_q8_ = mean;
    flags_a_ = d.flags;
    have_a_ = have;
    return;
  }
  if (!have || !have_a_) return;
  const cycle_q8 c = make_cycle(mean_a_q8_, mean);
  const auto flags = static_cast<uint8_t>(flags_a_ | d.flags);
  if ((cfg_.flags & protocol::cfg_compensate) != 0) {
    protocol::compensated_msg m;
    m.cycle = stat_.cycle;
    m.rate_q8 = saturate(int64_t{c.rate_q8} - delta_n_q8_);
    m.bias_q8 = c.bias_q8;
    m.flags = flags;
    send(m);
  }
  if (!cal_wait_a_ && cal_.add(c.rate_q8, flags)) {
    const protocol::cal_result_msg r = cal_.result();
    if (r.delta_n_q8 != delta_n_q8_) delta_n_dirty_ = true;
    delta_n_q8_ = r.delta_n_q8;
    send(r);
    if (stop_after_cal_) {
      ++stat_.cycle;
      stop_run();
    }
  }
}

void device::finish_dwell(uint32_t now) {
  dwell_.t_end_ticks = now;
  send(dwell_);
  if (method_pair()) {
    process_pair(dwell_);
    if (state_ != protocol::device_state::running) return;  // a calibration ended the run
  }
  position_ = static_cast<uint8_t>(position_ + 1);
  if (position_ >= cfg_.n_positions) {
    position_ = 0;
    ++stat_.cycle;
  }
  // On a port with short passes the turn starts in the next pass: the dwell's frames and the
  // turn's first intervals in one pass made the F149's longest pass (docs/FIRMWARE.md).
  if (facts_.short_passes) {
    turn_due_ = true;
    return;
  }
  begin_turn(position_, now);
}

}  // namespace gyroflip::fw
