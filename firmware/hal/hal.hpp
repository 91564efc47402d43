/// \file
/// \brief The firmware's hardware abstraction (Zephyr-style: a table of operations and a context
/// pointer). Nothing else in firmware/ reaches hardware; a port (ports/<target>/) fills the table
/// with register accesses, and the host port with models. Every operation is non-blocking except
/// spi_transfer, which moves a few bytes at the SPI clock.
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "firmware/protocol/status.hpp"

namespace gyroflip::fw {

using protocol::status;

/// One completed period of a PWM (duty-cycle) input, captured on its edges by a timer: the high
/// time T1 and the period T2 in timer ticks (ADXL202 Rev. B, p. 1: A = (T1/T2 - 0.5) / 12.5 %).
struct pwm_period {
  uint32_t high_ticks = 0;
  uint32_t period_ticks = 0;
};

struct hal_ops {
  /// Full-duplex SPI: clocks out tx[0..n) and stores what came in to rx[0..n) (rx may be tx).
  status (*spi_transfer)(void* ctx, const uint8_t* tx, uint8_t* rx, size_t n);
  /// Chip select of the ADC (true: selected, the line low).
  void (*spi_select)(void* ctx, bool selected);
  /// The ADC's RDY line is low (a conversion result is ready).
  bool (*rdy_low)(void* ctx);
  /// Writes the 8-bit stepper port: the low nibble drives motor 0's four coils, the high nibble
  /// motor 1's.
  void (*stepper_port)(void* ctx, uint8_t value);
  /// The table's home switch is closed (ports without one return false).
  bool (*home_switch)(void* ctx);
  /// Takes the oldest period of PWM input `axis` (0: x, 1: y) captured since the last call;
  /// false when none completed.
  bool (*pwm_capture)(void* ctx, uint8_t axis, pwm_period* out);
  /// The received UART bytes, in place: first frees the `taken` first bytes of the span the
  /// last call returned (the caller has read them), then returns how many bytes wait one after
  /// the other in the port's receive queue, the first at *at (0: none; a queue that wraps gives
  /// the rest at the next call). One call per block, not per byte: on the MSP430F149 an
  /// indirect call per byte was a tenth of a received byte's cost (docs/PERFORMANCE.md).
  size_t (*uart_read)(void* ctx, size_t taken, const volatile uint8_t** at);
  /// Hands bytes to the UART transmitter, in order: returns how many of the `n` it took (the
  /// rest: try again later).
  size_t (*uart_write)(void* ctx, const uint8_t* bytes, size_t n);
  /// The free-running tick counter (wraps; differences are taken modulo 2^32).
  uint32_t (*ticks)(void* ctx);
  /// Restarts the watchdog.
  void (*watchdog_kick)(void* ctx);
  /// Called in each turn of a bounded busy wait (ADC calibration at boot): a port may idle the
  /// CPU until the next interrupt; the host port advances its virtual clock by one tick.
  void (*busy_wait)(void* ctx);
  /// Stack bytes never used since boot (a port paints its stack at reset and finds the
  /// high-water mark); 0xFFFF when the port cannot tell.
  uint16_t (*stack_free)(void* ctx);
  /// protocol::clock_fault bits of the oscillator faults the port has seen since boot (a
  /// crystal that failed to start or stopped).
  uint8_t (*clock_faults)(void* ctx);

  // Optional operations: null when the port has none (the core then does the work in poll()).
  /// Arms the step timer: the port calls device::on_step_timer at tick `due` (at once when that
  /// has passed); `arm` false disarms it. Null: poll() takes the steps that are due.
  void (*step_timer)(void* ctx, bool arm, uint32_t due);
  /// Enters (true) or leaves (false) a section no interrupt that calls into the core may enter
  /// (not nested). Null: the port has no such interrupt.
  void (*critical)(void* ctx, bool enter);
  /// Non-volatile record `id` (nv_board, nv_delta_n; the MSP430F149's information flash): reads
  /// `n` bytes; false when the port keeps none.
  bool (*nv_read)(void* ctx, uint8_t id, uint8_t* buf, size_t n);
  /// Replaces record `id` with `n` bytes (erases its segment first); false on failure.
  bool (*nv_write)(void* ctx, uint8_t id, const uint8_t* buf, size_t n);
};

/// Non-volatile records (hal_ops::nv_read): the board's own serial, written once by the lab that
/// builds it (docs/HARDWARE.md, "Bring-up"), and the dN in force, written by the device.
inline constexpr uint8_t nv_board = 0;
inline constexpr uint8_t nv_delta_n = 1;

/// What a port keeps, for the core, in memory a reset does not clear (the MSP430F149's .noinit
/// RAM): the running boot's next frame number and its DWELLs so far, which the next boot
/// reports in INFO (prev_next_seq, prev_dwells) so that a host can count what it never got.
struct retained_counters {
  uint16_t next_seq = 0;
  uint32_t dwells = 0;
};

/// What a port tells the core at boot: why the device started and how often it did.
struct boot_info {
  uint8_t reset_cause = 0;  ///< a protocol::reset_cause value
  uint16_t boot_count = 0;  ///< starts since power-on, kept in memory a reset does not clear
  /// The previous boot's counters (valid when `prev_valid`: a reset that kept RAM).
  bool prev_valid = false;
  retained_counters prev{};
  /// Where the port keeps this boot's counters (null: nowhere).
  retained_counters* keep = nullptr;
};

/// A port's hardware: the operations and their context.
struct hal {
  const hal_ops* ops;
  void* ctx;
  uint32_t tick_hz;  ///< rate of ticks()
  /// The port calls device::on_rdy from the ADC's /RDY interrupt (false: poll() does).
  bool rdy_irq = false;

  status spi_transfer(const uint8_t* tx, uint8_t* rx, size_t n) const {
    return ops->spi_transfer(ctx, tx, rx, n);
  }
  void spi_select(bool on) const { ops->spi_select(ctx, on); }
  [[nodiscard]] bool rdy_low() const { return ops->rdy_low(ctx); }
  void stepper_port(uint8_t v) const { ops->stepper_port(ctx, v); }
  [[nodiscard]] bool home_switch() const { return ops->home_switch(ctx); }
  bool pwm_capture(uint8_t axis, pwm_period* out) const { return ops->pwm_capture(ctx, axis, out); }
  size_t uart_read(size_t taken, const volatile uint8_t** at) const {
    return ops->uart_read(ctx, taken, at);
  }
  size_t uart_write(const uint8_t* bytes, size_t n) const { return ops->uart_write(ctx, bytes, n); }
  [[nodiscard]] uint32_t ticks() const { return ops->ticks(ctx); }
  void watchdog_kick() const { ops->watchdog_kick(ctx); }
  void busy_wait() const { ops->busy_wait(ctx); }
  [[nodiscard]] uint16_t stack_free() const { return ops->stack_free(ctx); }
  [[nodiscard]] uint8_t clock_faults() const { return ops->clock_faults(ctx); }
  [[nodiscard]] bool has_step_timer() const { return ops->step_timer != nullptr; }
  void step_timer(bool arm, uint32_t due) const {
    if (ops->step_timer != nullptr) ops->step_timer(ctx, arm, due);
  }
  void critical(bool enter) const {
    if (ops->critical != nullptr) ops->critical(ctx, enter);
  }
  bool nv_read(uint8_t id, uint8_t* buf, size_t n) const {
    return ops->nv_read != nullptr && ops->nv_read(ctx, id, buf, n);
  }
  bool nv_write(uint8_t id, const uint8_t* buf, size_t n) const {
    return ops->nv_write != nullptr && ops->nv_write(ctx, id, buf, n);
  }
};

}  // namespace gyroflip::fw
