/// \file
/// \brief The sequencer and sampler of the firmware core (device.hpp): turn -> settle ->
/// acquire N gyro and n_temp temperature conversions -> report -> turn to the next position of
/// the angle table. Every wait is a state checked against the tick counter, so commands are
/// served between any two conversions.
#include "firmware/core/device.hpp"
#include "firmware/core/timebase.hpp"
#include "firmware/util/intmath.hpp"

namespace gyroflip::fw {

using protocol::status;

stepper::ramp device::ramp() const {
  return {cfg_.start_rate_sps, cfg_.step_rate_sps, cfg_.ramp_sps2};
}

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

void device::apply_adc_config() {
  const bool chop = (cfg_.flags & protocol::cfg_chop) != 0;
  conv_ticks_ =
      mclk_to_ticks(ad7739::conversion_mclk(chop, cfg_.filter_word), hw_.tick_hz, facts_.mclk_hz);
  settle_ticks_ = ms_to_ticks(cfg_.settle_ms, hw_.tick_hz);
  status_ticks_ = ms_to_ticks(cfg_.status_period_ms, hw_.tick_hz);
  // Three conversion times (issue 8), plus one tick for the quantisation of the start time.
  timeout_ticks_ = 3 * conv_ticks_ + 1;
  const uint8_t channels[2] = {cfg_.gyro_channel, cfg_.temp_channel};
  for (const uint8_t ch : channels) {
    status s = adc_.setup_channel(ch, ad7739::range_bipolar_2v5);
    if (s == status::ok) s = adc_.set_conversion_time(ch, chop, cfg_.filter_word);
    // Each self-calibration step takes about one conversion (data sheet: at the channel's
    // conversion time); four are allowed.
    if (s == status::ok) s = adc_.self_calibrate(ch, 4 * conv_ticks_ + 1);
    if (s != status::ok) error(s, protocol::error_source::adc, ch);
  }
  set_coils(state_ != protocol::device_state::idle);
}

void device::start_run(bool by_calibrate) {
  stat_.cycle = 0;
  position_ = 0;
  gyro_index_ = 0;
  stop_after_cal_ = by_calibrate;
  state_ = protocol::device_state::running;
  apply_adc_config();
  const uint32_t now = hw_.ticks();
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
  phase_ = phase::idle;
  state_ = protocol::device_state::idle;
  converting_ = false;
  cal_.cancel();
  set_coils(false);
}

void device::begin_turn(uint8_t to_position, uint32_t now) {
  const stepper::motor& flip = motors_[cfg_.flip_motor & 1];
  const int32_t steps = protocol::turn_steps(cfg_, flip.position, to_position);
  phase_start_ = now;
  set_coils(true);
  if (steps == 0) {
    phase_ = phase::settling;
    return;
  }
  mover_.begin(steps, now);
  phase_ = phase::turning;
}

void device::begin_dwell(uint32_t now) {
  dwell_ = protocol::dwell_msg{};
  dwell_.cycle = stat_.cycle;
  dwell_.position = position_;
  dwell_.t_start_ticks = now;
  if (step_fault_) dwell_.flags |= protocol::dwell_step_fault;
  step_fault_ = false;
  attempts_ = 0;
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
  phase_ = phase::gyro;
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
  // Hold still while a closed switch settles; step on while it is open.
  if (!closed && static_cast<int32_t>(now - next_home_step_) >= 0) {
    flip.step(-1);
    write_port();
    ++home_steps_;
    next_home_step_ +=
        stepper::step_interval({cfg_.start_rate_sps, cfg_.start_rate_sps, 1}, 0, 1, hw_.tick_hz);
  }
  // After any closed reading the next step waits a whole debounce time: a contact bouncing on
  // arrival reads open half the time, and stepping on then would leave the home step.
  if (closed) next_home_step_ = now + home_debounce_ticks;
}

void device::step_sequencer(uint32_t now) {
  switch (phase_) {
    case phase::idle:
      return;
    case phase::homing:
      return step_homing(now);
    case phase::turning: {
      const uint32_t before = mover_.steps_done();
      stepper::motor& flip = motors_[cfg_.flip_motor & 1];
      stepper::motor& other = motors_[1 - (cfg_.flip_motor & 1)];
      const bool moving = mover_.poll(now, ramp(), hw_.tick_hz, flip, other,
                                      static_cast<stepper::follower>(cfg_.other_motor));
      if (mover_.steps_done() != before) write_port();
      if (!moving) {
        phase_ = phase::settling;
        phase_start_ = now;
      }
      return;
    }
    case phase::settling:
      if (now - phase_start_ >= settle_ticks_) begin_dwell(now);
      return;
    case phase::gyro:
      return step_conversion(now, true);
    case phase::temp:
      return step_conversion(now, false);
  }
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

void device::step_conversion(uint32_t now, bool gyro) {
  const uint16_t target = gyro ? cfg_.n_avg : cfg_.n_temp;
  if (attempts_ >= target) {
    if (gyro) flush_raw();
    if (gyro && cfg_.n_temp != 0) {
      attempts_ = 0;
      phase_ = phase::temp;
      return;
    }
    return finish_dwell(now);
  }
  capture_pwm();
  const uint8_t ch = gyro ? cfg_.gyro_channel : cfg_.temp_channel;
  if (!converting_) {
    // A result nobody read (a RDY that came after its timeout) holds /RDY low through the next
    // mode write: read it away first, so that the wait below is for the new conversion.
    if (adc_.ready()) {
      int32_t old = 0;
      uint8_t st = 0;
      static_cast<void>(adc_.read_result(cfg_.gyro_channel, &old, &st));
      static_cast<void>(adc_.read_result(cfg_.temp_channel, &old, &st));
    }
    if (adc_.start_single(ch) == status::ok) {
      conv_start_ = now;
      converting_ = true;
      return;
    }
    // The bus failed: the attempt counts (a dead ADC must not hold the dwell forever), flagged.
    ++attempts_;
    dwell_.flags |= protocol::dwell_start_failed;
    if (stat_.start_failures != 0xFFFF) ++stat_.start_failures;
    if (gyro) {
      flush_raw();  // a RAW block holds consecutive conversions only
      ++gyro_index_;
    }
    if (!fault_reported_) {
      fault_reported_ = true;
      error(status::bus_error, protocol::error_source::adc, gyro_index_);
    }
    return;
  }
  if (adc_.ready()) return take_result(now, gyro, ch);
  if (now - conv_start_ <= timeout_ticks_) return;
  // RDY never came: count it, report the first of this dwell, and go on with the next one.
  converting_ = false;
  ++attempts_;
  dwell_.flags |= protocol::dwell_rdy_timeout;
  if (stat_.rdy_timeouts != 0xFFFF) ++stat_.rdy_timeouts;
  if (gyro) {
    flush_raw();
    ++gyro_index_;
  }
  if (!fault_reported_) {
    fault_reported_ = true;
    error(status::timeout, protocol::error_source::adc, gyro_index_);
  }
}

// /RDY is low: take the result if it is this conversion's. The dump-mode status byte must name
// this channel with its RDY bit set, and the conversion time must have passed: a result earlier
// than that is an older one (the AD7739 drives /RDY high only in the scaling time at the end of
// the new conversion, data sheet Rev. A). A refused result is counted and the wait goes on.
void device::take_result(uint32_t now, bool gyro, uint8_t ch) {
  int32_t code = 0;
  uint8_t st = 0;
  const status s = adc_.read_result(ch, &code, &st);
  if (s != status::ok) {
    converting_ = false;
    ++attempts_;
    dwell_.flags |= protocol::dwell_start_failed;
    if (stat_.start_failures != 0xFFFF) ++stat_.start_failures;
    return;
  }
  const bool mine = (st >> ad7739::chst_channel_shift) == ch && (st & ad7739::chst_rdy) != 0;
  const bool in_time = now - conv_start_ + 1 >= conv_ticks_;
  if (!mine || !in_time) {
    dwell_.flags |= protocol::dwell_stale;
    if (stat_.stale_results != 0xFFFF) ++stat_.stale_results;
    return;
  }
  converting_ = false;
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
  begin_turn(position_, now);
}

}  // namespace gyroflip::fw
