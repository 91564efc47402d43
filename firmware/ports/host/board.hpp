/// \file
/// \brief The host port: the firmware core's HAL backed by models, on a virtual clock that the
/// caller advances (tests; the emulator of the host side). The AD7739 is ad7739_model; the
/// stepper port decodes each nibble's full-step sequence into a position (and counts any
/// transition that is not one step); the home switch closes at a chosen position; the PWM
/// inputs give periods of a set duty; the UART moves 10 bits per byte at 115200 b/s.
/// Freestanding like the rest of firmware/.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "firmware/drivers/ad7739/convert.hpp"
#include "firmware/hal/hal.hpp"
#include "firmware/ports/host/ad7739_model.hpp"
#include "firmware/ports/host/stepper_model.hpp"
#include "firmware/util/ring.hpp"

namespace gyroflip::fw::model {

class host_board {
 public:
  static constexpr uint32_t tick_hz = 32768;
  static constexpr uint32_t baud = 115200;

  host_board(ad7739_model::source_fn source, void* ctx, uint32_t mclk_hz = ad7739::mclk_hz_nominal);
  host_board(const host_board&) = delete;
  host_board& operator=(const host_board&) = delete;

  [[nodiscard]] const hal& hw() const { return hal_; }

  uint32_t now = 0;  ///< the virtual tick counter
  ad7739_model adc;

  stepper_port_model motors;  ///< the stepper port, decoded
  /// The home switch closes while motor 0's decoded position equals this modulo steps_per_rev.
  bool has_home = true;
  int32_t home_at = 0;
  int32_t steps_per_rev = 200;

  // PWM inputs: high time and period (ticks) of axis 0 (x) and 1 (y); 0 period = no signal.
  uint32_t pwm_high_ticks[2] = {0, 0};
  uint32_t pwm_period_ticks[2] = {0, 0};
  /// What the capture timer reports for each period, in its own ticks (the MSP430F149's Timer_B
  /// runs at SMCLK/8 = 691.2 kHz, finer than this board's tick): used instead of the two above when
  /// the period is not 0 (the emulator's accelerometer).
  uint32_t pwm_capture_high[2] = {0, 0};
  uint32_t pwm_capture_period[2] = {0, 0};

  /// The host sends bytes to the device (false when the receive queue is full).
  bool host_send(const uint8_t* p, size_t n) { return rx_.push(p, n); }
  /// Room in the receive queue.
  [[nodiscard]] size_t host_free() const { return rx_.free(); }
  /// Takes up to `cap` bytes the device has sent.
  size_t host_receive(uint8_t* out, size_t cap);
  /// While true the UART takes no byte (a stalled line: tests of the transmit ring).
  bool uart_stalled = false;
  /// What stack_free reports (the host cannot measure the core's stack).
  uint16_t stack_free = 0xFFFF;
  /// Oscillator faults the port reports (tests of the clock supervision).
  uint8_t clock_faults = 0;
  /// While true the tick counter does not move when the caller advances `now` (a dead tick
  /// crystal; ticks() returns `frozen_at`).
  bool ticks_frozen = false;
  uint32_t frozen_at = 0;
  /// The home switch bounces: for this many ticks after motor 0 arrives at the home position
  /// it reads closed only on every other tick.
  uint32_t home_bounce_ticks = 0;
  /// A noise spike: the switch reads closed at tick `home_glitch_at` (0: never), wherever the
  /// table stands.
  uint32_t home_glitch_at = 0;
  /// Times the watchdog was fed, and the tick of the last time.
  uint32_t watchdog_kicks = 0;
  uint32_t last_kick = 0;

  /// While true every SPI transfer fails (a broken bus: the core's start failures).
  bool spi_fails = false;

  /// Bytes the device sent that did not fit the host's queue (a test reads often enough).
  uint32_t tx_overflow = 0;

  /// The non-volatile records (hal_ops::nv_read: the board's information flash), erased (0xFF)
  /// until written; they outlive the device object, as flash outlives a reset.
  static constexpr size_t nv_record_cap = 16;
  uint8_t nv[2][nv_record_cap] = {{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
                                   0xFF, 0xFF, 0xFF, 0xFF, 0xFF},
                                  {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
                                   0xFF, 0xFF, 0xFF, 0xFF, 0xFF}};
  uint32_t nv_writes = 0;

 private:
  static status spi_transfer(void* c, const uint8_t* tx, uint8_t* rx, size_t n);
  static void spi_select(void* c, bool on);
  static bool rdy_low(void* c);
  static void stepper_port(void* c, uint8_t v);
  static bool home_switch(void* c);
  static bool pwm_capture(void* c, uint8_t axis, pwm_period* out);
  static size_t uart_read(void* c, size_t taken, const volatile uint8_t** at);
  static size_t uart_write(void* c, const uint8_t* bytes, size_t n);
  static uint32_t ticks(void* c);
  static void watchdog_kick(void* c);
  static void busy_wait(void* c);
  static uint16_t stack_free_op(void* c);
  static uint8_t clock_faults_op(void* c);
  static bool nv_read(void* c, uint8_t id, uint8_t* buf, size_t n);
  static bool nv_write(void* c, uint8_t id, const uint8_t* buf, size_t n);
  // No step timer and no interrupts: the core takes steps and results in poll().
  static constexpr hal_ops ops_ = {
      spi_transfer,    spi_select, rdy_low, stepper_port,  home_switch, pwm_capture,
      uart_read,       uart_write, ticks,   watchdog_kick, busy_wait,   stack_free_op,
      clock_faults_op, nullptr,    nullptr, nv_read,       nv_write};

  hal hal_;
  byte_ring<1024> rx_;
  byte_ring<16384> tx_;
  uint64_t line_free_at_ = 0;  // when the UART's shift register is free, in ticks x baud
  uint32_t pwm_next_[2] = {0, 0};
  int32_t home_arrived_pos_ = 0x7FFFFFFF;  // motor 0's position when the bounce began
  uint32_t home_arrived_at_ = 0;
};

}  // namespace gyroflip::fw::model
