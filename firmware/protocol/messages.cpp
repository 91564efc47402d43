/// \file
/// \brief Message encodings (see messages.hpp; byte tables in docs/PROTOCOL.md).
#include "messages.hpp"

namespace gyroflip::protocol {

namespace {
constexpr size_t max_payload_of_configure = 64;  // 54 bytes (docs/PROTOCOL.md)
}  // namespace

void configure_msg::put(writer& w) const {
  w.u16(n_avg);
  w.u8(n_temp);
  w.u16(settle_ms);
  w.u8(n_positions);
  for (const int16_t p : pos_steps) w.i16(p);
  for (const uint16_t a : pos_cdeg) w.u16(a);
  w.u16(steps_per_rev);
  w.u16(step_rate_sps);
  w.u16(start_rate_sps);
  w.u16(ramp_sps2);
  w.u8(filter_word);
  w.u8(flags);
  w.u8(flip_motor);
  w.u8(other_motor);
  w.u8(gyro_channel);
  w.u8(temp_channel);
  w.u16(status_period_ms);
}

void configure_msg::get(reader& r) {
  n_avg = r.u16();
  n_temp = r.u8();
  settle_ms = r.u16();
  n_positions = r.u8();
  for (int16_t& p : pos_steps) p = r.i16();
  for (uint16_t& a : pos_cdeg) a = r.u16();
  steps_per_rev = r.u16();
  step_rate_sps = r.u16();
  start_rate_sps = r.u16();
  ramp_sps2 = r.u16();
  filter_word = r.u8();
  flags = r.u8();
  flip_motor = r.u8();
  other_motor = r.u8();
  gyro_channel = r.u8();
  temp_channel = r.u8();
  status_period_ms = r.u16();
}

void info_head::put_head(writer& w) const {
  w.u8(fw_major);
  w.u8(fw_minor);
  w.u8(fw_patch);
  w.u8(protocol);
  w.u32(serial);
  w.u32(mclk_hz);
  w.u32(tick_hz);
  w.u8(adc_revision);
  w.u16(max_n_avg);
  w.u8(max_raw_codes);
  w.u8(range);
  w.u8(reset_cause);
  w.u16(boot_count);
  w.u16(history_bytes);
  w.u8(board);
  w.u8(stored);
  w.i32(delta_n_q8);
  w.u16(prev_next_seq);
  w.u32(prev_dwells);
}

void info_head::get_head(reader& r) {
  fw_major = r.u8();
  fw_minor = r.u8();
  fw_patch = r.u8();
  protocol = r.u8();
  serial = r.u32();
  mclk_hz = r.u32();
  tick_hz = r.u32();
  adc_revision = r.u8();
  max_n_avg = r.u16();
  max_raw_codes = r.u8();
  range = r.u8();
  reset_cause = r.u8();
  boot_count = r.u16();
  history_bytes = r.u16();
  board = r.u8();
  stored = r.u8();
  delta_n_q8 = r.i32();
  prev_next_seq = r.u16();
  prev_dwells = r.u32();
}

void dwell_msg::put(writer& w) const {
  w.u32(cycle);
  w.u8(position);
  w.u8(flags);
  w.u32(t_start_ticks);
  w.u32(t_end_ticks);
  w.u16(n);
  w.i48(code_sum);
  w.i24(code_min);
  w.i24(code_max);
  w.u8(n_temp);
  w.i32(temp_sum);
  w.u32(ax_high_ticks);
  w.u32(ax_period_ticks);
  w.u32(ay_high_ticks);
  w.u32(ay_period_ticks);
}

void dwell_msg::get(reader& r) {
  cycle = r.u32();
  position = r.u8();
  flags = r.u8();
  t_start_ticks = r.u32();
  t_end_ticks = r.u32();
  n = r.u16();
  code_sum = r.i48();
  code_min = r.i24();
  code_max = r.i24();
  n_temp = r.u8();
  temp_sum = r.i32();
  ax_high_ticks = r.u32();
  ax_period_ticks = r.u32();
  ay_high_ticks = r.u32();
  ay_period_ticks = r.u32();
}

void raw_msg::put(writer& w) const {
  if (count > max_codes) {
    w.ok = false;
    return;
  }
  w.u32(first_index);
  w.u8(count);
  const size_t n = size_t{3} * count;
  if (uint8_t* at = w.take(n)) {
    for (size_t i = 0; i < n; ++i) at[i] = packed[i];
  }
}

void raw_msg::get(reader& r) {
  first_index = r.u32();
  count = r.u8();
  if (count > max_codes) {
    r.ok = false;
    return;
  }
  const size_t n = size_t{3} * count;
  if (const uint8_t* at = r.take(n)) {
    for (size_t i = 0; i < n; ++i) packed[i] = at[i];
  }
}

void status_msg::put(writer& w) const {
  w.u8(state);
  w.u32(uptime_ticks);
  w.u32(cycle);
  w.u32(frames_sent);
  w.u16(frames_dropped);
  w.u16(rx_frames_ok);
  w.u16(rx_errors);
  w.u16(rdy_timeouts);
  w.u8(last_error);
  w.u16(retransmits);
  w.u16(history_oldest);
  w.u16(line_corrected);
  w.u16(line_uncorrectable);
  w.u16(start_failures);
  w.u16(stale_results);
  w.u16(stack_free);
  w.u8(clock_faults);
  w.u16(boot_count);
}

void status_msg::get(reader& r) {
  state = r.u8();
  uptime_ticks = r.u32();
  cycle = r.u32();
  frames_sent = r.u32();
  frames_dropped = r.u16();
  rx_frames_ok = r.u16();
  rx_errors = r.u16();
  rdy_timeouts = r.u16();
  last_error = r.u8();
  retransmits = r.u16();
  history_oldest = r.u16();
  line_corrected = r.u16();
  line_uncorrectable = r.u16();
  start_failures = r.u16();
  stale_results = r.u16();
  stack_free = r.u16();
  clock_faults = r.u8();
  boot_count = r.u16();
}

void error_msg::put(writer& w) const {
  w.u8(code);
  w.u8(what);
  w.u32(value);
}

void error_msg::get(reader& r) {
  code = r.u8();
  what = r.u8();
  value = r.u32();
}

void ack_msg::put(writer& w) const {
  w.u16(seq);
  w.u8(of_type);
  w.u16(at_seq);
}

void ack_msg::get(reader& r) {
  seq = r.u16();
  of_type = r.u8();
  at_seq = r.u16();
}

void nak_msg::put(writer& w) const {
  w.u16(seq);
  w.u8(of_type);
  w.u8(reason);
}

void nak_msg::get(reader& r) {
  seq = r.u16();
  of_type = r.u8();
  reason = r.u8();
}

void compensated_msg::put(writer& w) const {
  w.u32(cycle);
  w.i32(rate_q8);
  w.i32(bias_q8);
  w.u8(flags);
}

void compensated_msg::get(reader& r) {
  cycle = r.u32();
  rate_q8 = r.i32();
  bias_q8 = r.i32();
  flags = r.u8();
}

void cal_result_msg::put(writer& w) const {
  w.u16(cycles);
  w.i32(delta_n_q8);
  w.u32(std_q8);
  w.u8(flags);
}

void cal_result_msg::get(reader& r) {
  cycles = r.u16();
  delta_n_q8 = r.i32();
  std_q8 = r.u32();
  flags = r.u8();
}

namespace {

// u8 count, then count u16: GONE and RESEND.
void put_seqs(writer& w, uint8_t count, const uint16_t* seqs, uint8_t max) {
  if (count > max) {
    w.ok = false;
    return;
  }
  w.u8(count);
  for (uint8_t i = 0; i < count; ++i) w.u16(seqs[i]);
}
void get_seqs(reader& r, uint8_t& count, uint16_t* seqs, uint8_t max) {
  count = r.u8();
  if (count > max) {
    r.ok = false;
    return;
  }
  for (uint8_t i = 0; i < count; ++i) seqs[i] = r.u16();
}

}  // namespace

void gone_msg::put(writer& w) const {
  put_seqs(w, count, seqs, max_seqs);
}
void gone_msg::get(reader& r) {
  get_seqs(r, count, seqs, max_seqs);
}
void resend_msg::put(writer& w) const {
  put_seqs(w, count, seqs, max_seqs);
}
void resend_msg::get(reader& r) {
  get_seqs(r, count, seqs, max_seqs);
}

uint16_t configure_crc(const configure_msg& c) {
  uint8_t b[max_payload_of_configure];
  writer w{b, sizeof b};
  c.put(w);
  return crc16(b, w.n);
}

bool crc_extra_of(uint8_t t, uint8_t& extra) {
  switch (static_cast<msg>(t)) {
    case msg::info:
      extra = info_msg::crc_extra;
      return true;
    case msg::dwell:
      extra = dwell_msg::crc_extra;
      return true;
    case msg::raw:
      extra = raw_msg::crc_extra;
      return true;
    case msg::status:
      extra = status_msg::crc_extra;
      return true;
    case msg::error:
      extra = error_msg::crc_extra;
      return true;
    case msg::ack:
      extra = ack_msg::crc_extra;
      return true;
    case msg::nak:
      extra = nak_msg::crc_extra;
      return true;
    case msg::compensated:
      extra = compensated_msg::crc_extra;
      return true;
    case msg::cal_result:
      extra = cal_result_msg::crc_extra;
      return true;
    case msg::ping:
      extra = ping_msg::crc_extra;
      return true;
    case msg::configure:
      extra = configure_msg::crc_extra;
      return true;
    case msg::start:
      extra = start_msg::crc_extra;
      return true;
    case msg::stop:
      extra = stop_msg::crc_extra;
      return true;
    case msg::home:
      extra = home_msg::crc_extra;
      return true;
    case msg::set_delta_n:
      extra = set_delta_n_msg::crc_extra;
      return true;
    case msg::calibrate:
      extra = calibrate_msg::crc_extra;
      return true;
    case msg::gone:
      extra = gone_msg::crc_extra;
      return true;
    case msg::resend:
      extra = resend_msg::crc_extra;
      return true;
  }
  return false;
}

}  // namespace gyroflip::protocol
