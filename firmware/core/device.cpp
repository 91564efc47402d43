/// \file
/// \brief The firmware core's link and commands (device.hpp); the sequencer is in sequencer.cpp.
#include "firmware/core/device.hpp"

#include "firmware/core/budget.hpp"

namespace gyroflip::fw {

using protocol::status;

status check_config(const protocol::configure_msg& c, uint32_t mclk_hz) {
  const int32_t span = int32_t{c.pos_b_steps} - c.pos_a_steps;
  const int32_t span_abs = span < 0 ? -span : span;
  const bool ok = c.n_avg >= 1 && c.n_temp <= max_n_temp && span != 0 && c.steps_per_rev >= 4 &&
                  span_abs < c.steps_per_rev && c.step_rate_sps >= 1 &&
                  c.step_rate_sps <= max_step_rate_sps && c.start_rate_sps >= 1 &&
                  c.start_rate_sps <= c.step_rate_sps && c.ramp_sps2 >= 1 &&
                  c.filter_word >= ad7739::fw_min && c.filter_word <= ad7739::fw_max &&
                  (c.flags & ~protocol::cfg_all) == 0 && c.flip_motor <= 1 && c.other_motor <= 3 &&
                  c.gyro_channel <= 3 && c.temp_channel <= 3 && c.gyro_channel != c.temp_channel &&
                  c.status_period_ms <= max_status_period_ms;
  if (!ok) return status::bad_arg;
  // The link must carry the worst case, or frames would be dropped by design.
  return worst_bytes_per_s(c, mclk_hz) <= link_bytes_per_s ? status::ok : status::bad_arg;
}

void device::boot() {
  hw_.watchdog_kick();
  write_port();
  const status s = adc_.reset();
  if (s == status::ok) adc_.read_revision(&adc_revision_);
  if (s != status::ok || adc_revision_ == 0x00 || adc_revision_ == 0xFF)
    error(status::bus_error, protocol::error_source::adc, adc_revision_);
  apply_adc_config();
  last_status_ = hw_.ticks();
  send_info();
  transmit();
}

void device::poll() {
  hw_.watchdog_kick();
  receive();
  const uint32_t now = hw_.ticks();
  step_sequencer(now);
  if (cfg_.status_period_ms != 0 && now - last_status_ >= status_ticks_) {
    last_status_ = now;
    send_status();
  }
  transmit();
}

void device::receive() {
  uint8_t b = 0;
  // A bounded number per pass, so a flooded line cannot starve the sequencer.
  for (int i = 0; i < 64 && hw_.uart_read(&b); ++i) {
    if (rx_.push(b)) handle(rx_.current());
  }
}

void device::transmit() {
  uint8_t b = 0;
  while (tx_.peek(&b) && hw_.uart_write(b)) tx_.pop();
}

bool device::queue(size_t n, bool droppable) {
  // The sequence number is used even when the frame is dropped: the host then counts it missing.
  ++tx_seq_;
  if (n != 0 && tx_.free() >= n + (droppable ? tx_reserve_bytes : 0) && tx_.push(scratch_, n)) {
    ++stat_.frames_sent;
    return true;
  }
  if (stat_.frames_dropped != 0xFFFF) ++stat_.frames_dropped;
  return false;
}

void device::ack(const protocol::frame& f) {
  protocol::ack_msg a;
  a.seq = f.seq;
  a.of_type = f.type;
  send(a);
}

void device::nak(const protocol::frame& f, status why) {
  protocol::nak_msg n;
  n.seq = f.seq;
  n.of_type = f.type;
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

void device::send_info() {
  protocol::info_msg m;
  m.fw_major = fw_version_major;
  m.fw_minor = fw_version_minor;
  m.fw_patch = fw_version_patch;
  m.protocol = protocol::protocol_version;
  m.serial = facts_.serial;
  m.mclk_hz = facts_.mclk_hz;
  m.tick_hz = hw_.tick_hz;
  m.adc_revision = adc_revision_;
  m.max_n_avg = max_n_avg;
  m.max_raw_codes = protocol::raw_msg::max_codes;
  m.range = ad7739::range_bipolar_2v5;
  m.config = cfg_;
  send(m);
}

void device::send_status() {
  stat_.state = static_cast<uint8_t>(state_);
  stat_.uptime_ticks = hw_.ticks();
  const protocol::decoder_counts& c = rx_.counts();
  stat_.rx_frames_ok = static_cast<uint16_t>(c.good);
  stat_.rx_errors = static_cast<uint16_t>(c.bad());
  send(stat_);
}

void device::handle(const protocol::frame& f) {
  const bool idle = state_ == protocol::device_state::idle;
  switch (static_cast<protocol::msg>(f.type)) {
    case protocol::msg::ping: {
      protocol::ping_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      ack(f);
      return send_info();
    }
    case protocol::msg::configure: {
      protocol::configure_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      if (!idle) return nak(f, status::busy);
      if (const status s = check_config(m, facts_.mclk_hz); s != status::ok) return nak(f, s);
      cfg_ = m;
      apply_adc_config();
      return ack(f);
    }
    case protocol::msg::start: {
      protocol::start_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      if (idle) start_run(false);
      return ack(f);
    }
    case protocol::msg::stop: {
      protocol::stop_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      stop_run();
      ack(f);
      return send_status();
    }
    case protocol::msg::home: {
      protocol::home_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      if (!idle) return nak(f, status::busy);
      home_then_run_ = false;
      state_ = protocol::device_state::homing;
      phase_ = phase::homing;
      home_steps_ = 0;
      next_home_step_ = hw_.ticks();
      return ack(f);
    }
    case protocol::msg::set_delta_n: {
      protocol::set_delta_n_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      delta_n_q8_ = m.delta_n_q8;
      return ack(f);
    }
    case protocol::msg::calibrate: {
      protocol::calibrate_msg m;
      if (!f.as(m)) return nak(f, status::bad_frame);
      if (m.cycles < 2) return nak(f, status::bad_arg);
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

}  // namespace gyroflip::fw
