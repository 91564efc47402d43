/// \file
/// \brief The host port's models (board.hpp).
#include "firmware/ports/host/board.hpp"

namespace gyroflip::fw::model {

namespace {
host_board& self(void* c) {
  return *static_cast<host_board*>(c);
}
}  // namespace

host_board::host_board(ad7739_model::source_fn source, void* ctx, uint32_t mclk_hz)
    : adc(tick_hz, mclk_hz, source, ctx), hal_{&ops_, this, tick_hz, false} {}

size_t host_board::host_receive(uint8_t* out, size_t cap) {
  size_t n = 0;
  while (n < cap && tx_.peek(out + n)) {
    tx_.pop();
    ++n;
  }
  return n;
}

status host_board::spi_transfer(void* c, const uint8_t* tx, uint8_t* rx, size_t n) {
  host_board& b = self(c);
  if (b.spi_fails) return status::bus_error;
  for (size_t i = 0; i < n; ++i) rx[i] = b.adc.transfer(tx[i], b.now);
  return status::ok;
}

void host_board::spi_select(void* c, bool on) {
  self(c).adc.select(on);
}

bool host_board::rdy_low(void* c) {
  host_board& b = self(c);
  return b.adc.rdy_low(b.now);
}

void host_board::stepper_port(void* c, uint8_t v) {
  self(c).motors.write(v);
}

bool host_board::home_switch(void* c) {
  host_board& b = self(c);
  if (b.home_glitch_at != 0 && b.now == b.home_glitch_at) return true;
  if (!b.has_home || b.steps_per_rev <= 0) return false;
  const int32_t pos = b.motors.position[0];
  if ((pos - b.home_at) % b.steps_per_rev != 0) return false;
  if (pos != b.home_arrived_pos_) {
    b.home_arrived_pos_ = pos;
    b.home_arrived_at_ = b.now;
  }
  // Contact bounce: closed on every other tick until it settles.
  if (b.now - b.home_arrived_at_ < b.home_bounce_ticks) return (b.now & 1u) == 0;
  return true;
}

bool host_board::pwm_capture(void* c, uint8_t axis, pwm_period* out) {
  host_board& b = self(c);
  const uint8_t a = axis & 1u;
  if (b.pwm_period_ticks[a] == 0) return false;
  if (static_cast<int32_t>(b.now - (b.pwm_next_[a] + b.pwm_period_ticks[a])) < 0) return false;
  // Periods that ended long ago (no capture for a while) are lost, as with a capture register.
  if (b.now - b.pwm_next_[a] > 2 * b.pwm_period_ticks[a])
    b.pwm_next_[a] = b.now - b.pwm_period_ticks[a];
  b.pwm_next_[a] += b.pwm_period_ticks[a];
  const bool fine = b.pwm_capture_period[a] != 0;
  out->high_ticks = fine ? b.pwm_capture_high[a] : b.pwm_high_ticks[a];
  out->period_ticks = fine ? b.pwm_capture_period[a] : b.pwm_period_ticks[a];
  return true;
}

size_t host_board::uart_read(void* c, size_t taken, const volatile uint8_t** at) {
  host_board& b = self(c);
  b.rx_.drop(taken);
  const uint8_t* first = nullptr;
  const size_t n = b.rx_.span(&first);
  *at = first;
  return n;
}

// One byte a byte time at 115 200 b/s (8N1): the UART takes the first byte when the line is
// free, and the others wait for later calls.
size_t host_board::uart_write(void* c, const uint8_t* bytes, size_t n) {
  host_board& b = self(c);
  const uint64_t now_scaled = uint64_t{b.now} * baud;
  if (n == 0 || b.uart_stalled || now_scaled < b.line_free_at_) return 0;
  b.line_free_at_ = now_scaled + uint64_t{10} * tick_hz;  // 10 bits per byte (8N1)
  if (!b.tx_.push(bytes, 1)) ++b.tx_overflow;
  return 1;
}

uint32_t host_board::ticks(void* c) {
  const host_board& b = self(c);
  return b.ticks_frozen ? b.frozen_at : b.now;
}

void host_board::watchdog_kick(void* c) {
  host_board& b = self(c);
  ++b.watchdog_kicks;
  b.last_kick = b.now;
}

uint16_t host_board::stack_free_op(void* c) {
  return self(c).stack_free;
}

uint8_t host_board::clock_faults_op(void* c) {
  return self(c).clock_faults;
}

bool host_board::nv_read(void* c, uint8_t id, uint8_t* buf, size_t n) {
  host_board& b = self(c);
  if (id > 1 || n > nv_record_cap) return false;
  for (size_t i = 0; i < n; ++i) buf[i] = b.nv[id][i];
  return true;
}

bool host_board::nv_write(void* c, uint8_t id, const uint8_t* buf, size_t n) {
  host_board& b = self(c);
  if (id > 1 || n > nv_record_cap) return false;
  for (size_t i = 0; i < nv_record_cap; ++i) b.nv[id][i] = i < n ? buf[i] : 0xFF;
  ++b.nv_writes;
  return true;
}

void host_board::busy_wait(void* c) {
  ++self(c).now;
}

}  // namespace gyroflip::fw::model
