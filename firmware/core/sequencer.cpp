/// \file
/// \brief The sequencer and sampler of the firmware core (device.hpp): turn -> settle ->
/// acquire N gyro and n_temp temperature conversions -> report -> turn. Every wait is a state
/// checked against the tick counter, so commands are served between any two conversions.
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
  stepper::motor& other = motors_[1 - (cfg_.flip_motor & 1)];
  other.energised =
      static_cast<protocol::other_motor>(cfg_.other_motor) != protocol::other_motor::off &&
      other.energised;
  write_port();
}

int32_t device::turn_steps(uint8_t to_position) const {
  const stepper::motor& flip = motors_[cfg_.flip_motor & 1];
  const int32_t target = to_position == 0 ? cfg_.pos_a_steps : cfg_.pos_b_steps;
  if ((cfg_.flags & protocol::cfg_one_way) == 0) return target - flip.position;
  // One way (rotary joint): always in the direction A -> B, the shorter way there, the rest of
  // the revolution back.
  const int32_t rev = cfg_.steps_per_rev;
  const int32_t dir = cfg_.pos_b_steps > cfg_.pos_a_steps ? 1 : -1;
  int32_t d = (dir * (target - flip.position)) % rev;
  if (d < 0) d += rev;
  return dir * d;
}

void device::start_run(bool by_calibrate) {
  stat_.cycle = 0;
  position_ = 0;
  gyro_index_ = 0;
  stop_after_cal_ = by_calibrate;
  state_ = protocol::device_state::running;
  motors_[0].energised = true;
  motors_[1].energised = true;
  apply_adc_config();  // also sets the other motor's coils per its rule
  motors_[cfg_.flip_motor & 1].energised = true;
  write_port();
  const uint32_t now = hw_.ticks();
  if ((cfg_.flags & protocol::cfg_home) != 0) {
    home_then_run_ = true;
    home_steps_ = 0;
    next_home_step_ = now;
    phase_ = phase::homing;
  } else {
    begin_turn(turn_steps(0), now);
  }
}

void device::stop_run() {
  phase_ = phase::idle;
  state_ = protocol::device_state::idle;
  converting_ = false;
  cal_.cancel();
}

void device::begin_turn(int32_t steps, uint32_t now) {
  phase_start_ = now;
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
  timeout_reported_ = false;
  raw_.count = 0;
  if (position_ == 0) cal_wait_a_ = false;
  // Periods captured during the turn are not this dwell's tilt.
  pwm_period p;
  for (uint8_t axis = 0; axis < 2; ++axis)
    while (hw_.pwm_capture(axis, &p)) {
    }
  phase_ = phase::gyro;
}

void device::step_sequencer(uint32_t now) {
  switch (phase_) {
    case phase::idle:
      return;
    case phase::homing: {
      stepper::motor& flip = motors_[cfg_.flip_motor & 1];
      if (hw_.home_switch() || home_steps_ > cfg_.steps_per_rev) {
        if (!hw_.home_switch()) {
          error(status::timeout, protocol::error_source::stepper, home_steps_);
          step_fault_ = true;
        }
        flip.position = 0;
        if (home_then_run_) {
          state_ = protocol::device_state::running;
          begin_turn(turn_steps(0), now);
        } else {
          phase_ = phase::idle;
          state_ = protocol::device_state::idle;
        }
        return;
      }
      if (static_cast<int32_t>(now - next_home_step_) >= 0) {
        flip.step(-1);
        write_port();
        ++home_steps_;
        next_home_step_ += stepper::step_interval({cfg_.start_rate_sps, cfg_.start_rate_sps, 1}, 0,
                                                  1, hw_.tick_hz);
      }
      return;
    }
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
    if (adc_.start_single(ch) == status::ok) {
      conv_start_ = now;
      converting_ = true;
    }
    return;
  }
  if (adc_.ready()) {
    int32_t code = 0;
    converting_ = false;
    ++attempts_;
    if (adc_.read_data(ch, &code) != status::ok) return;
    if (!gyro) {
      dwell_.temp_sum += code;
      ++dwell_.n_temp;
      return;
    }
    if (dwell_.n == 0 || code < dwell_.code_min) dwell_.code_min = code;
    if (dwell_.n == 0 || code > dwell_.code_max) dwell_.code_max = code;
    if (code <= -ad7739::code_zero || code >= ad7739::code_zero - 1)
      dwell_.flags |= protocol::dwell_adc_clip;
    dwell_.code_sum += code;
    ++dwell_.n;
    if ((cfg_.flags & protocol::cfg_raw) != 0) {
      if (raw_.count == 0) raw_.first_index = gyro_index_;
      raw_.set(raw_.count++, code);
      if (raw_.count == protocol::raw_msg::max_codes) flush_raw();
    }
    ++gyro_index_;
    return;
  }
  if (now - conv_start_ <= timeout_ticks_) return;
  // RDY never came: count it, report the first of this dwell, and go on with the next one.
  converting_ = false;
  ++attempts_;
  dwell_.flags |= protocol::dwell_rdy_timeout;
  if (stat_.rdy_timeouts != 0xFFFF) ++stat_.rdy_timeouts;
  if (gyro) {
    flush_raw();  // a RAW block holds consecutive conversions only
    ++gyro_index_;
  }
  if (!timeout_reported_) {
    timeout_reported_ = true;
    error(status::timeout, protocol::error_source::adc, gyro_index_);
  }
}

void device::flush_raw() {
  if (raw_.count == 0) return;
  if (!send(raw_, true)) dwell_.flags |= protocol::dwell_raw_dropped;
  raw_.count = 0;
}

void device::finish_dwell(uint32_t now) {
  dwell_.t_end_ticks = now;
  send(dwell_);
  const bool have = dwell_.n != 0;
  const int32_t mean = have ? mean_q8(dwell_.code_sum, dwell_.n) : 0;
  if (position_ == 0) {
    mean_a_q8_ = mean;
    flags_a_ = dwell_.flags;
    have_a_ = have;
  } else {
    if (have && have_a_) {
      const cycle_q8 c = make_cycle(mean_a_q8_, mean);
      const uint8_t flags = static_cast<uint8_t>(flags_a_ | dwell_.flags);
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
          return stop_run();
        }
      }
    }
    ++stat_.cycle;
  }
  position_ ^= 1u;
  begin_turn(turn_steps(position_), now);
}

}  // namespace gyroflip::fw
