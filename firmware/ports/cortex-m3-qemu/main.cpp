/// \file
/// \brief The Cortex-M3 image (QEMU mps2-an385): the firmware core with a HAL whose UART is the
/// board's CMSDK APB UART0 and whose tick is SysTick (25 MHz CPU clock, counted down to 1 MHz
/// ticks), and whose AD7739, steppers and PWM inputs are in-image models (docs/FIRMWARE.md):
/// the register-level ad7739_model fed by model_codes.hpp, the stepper-port decoder, and a
/// fixed 40 % duty on both PWM inputs. It is a model of the rig, not the rig.
#include <stddef.h>
#include <stdint.h>

#include "firmware/core/device.hpp"
#include "firmware/ports/cortex-m3-qemu/model_codes.hpp"
#include "firmware/ports/host/ad7739_model.hpp"
#include "firmware/ports/host/stepper_model.hpp"

namespace {

using namespace gyroflip;

// CMSDK APB UART0 (QEMU mps2-an385): DATA, STATE (bit 0 TX full, bit 1 RX full), CTRL (bit 0 TX
// enable, bit 1 RX enable: without them QEMU drops the bytes), BAUDDIV.
struct cmsdk_uart {
  volatile uint32_t data, state, ctrl, intstatus, bauddiv;
};
cmsdk_uart& uart0() {
  return *reinterpret_cast<cmsdk_uart*>(0x40004000u);
}

// SysTick: CSR, RVR, CVR (a 24-bit down counter).
struct systick_regs {
  volatile uint32_t csr, rvr, cvr, calib;
};
systick_regs& systick() {
  return *reinterpret_cast<systick_regs*>(0xE000E010u);
}

constexpr uint32_t cpu_hz = 25000000;
constexpr uint32_t tick_hz = 1000000;
constexpr uint32_t cycles_per_tick = cpu_hz / tick_hz;

struct board_state {
  uint32_t last_cvr = 0;
  uint32_t cycle_rest = 0;
  uint32_t ticks = 0;
  fw::model::stepper_port_model motors;
  uint32_t pwm_next[2] = {0, 0};
};
board_state board;

uint32_t now_ticks() {
  const uint32_t cvr = systick().cvr & 0xFFFFFFu;
  const uint32_t elapsed = (board.last_cvr - cvr) & 0xFFFFFFu;  // it counts down and wraps
  board.last_cvr = cvr;
  board.cycle_rest += elapsed;
  board.ticks += board.cycle_rest / cycles_per_tick;
  board.cycle_rest %= cycles_per_tick;
  return board.ticks;
}

int32_t model_source(void*, uint8_t ch, uint32_t index) {
  if (ch != 0) return fw::qemu::model_temp;
  // The model's B is motor 0 at 100 steps (mod 200): the default configuration's positions.
  const int32_t p = ((board.motors.position[0] % 200) + 200) % 200;
  return fw::qemu::model_gyro_code(index, p == 100);
}

fw::model::ad7739_model adc(tick_hz, ad7739::mclk_hz_nominal, &model_source, nullptr);

fw::status spi_transfer(void*, const uint8_t* tx, uint8_t* rx, size_t n) {
  const uint32_t t = now_ticks();
  for (size_t i = 0; i < n; ++i) rx[i] = adc.transfer(tx[i], t);
  return fw::status::ok;
}
void spi_select(void*, bool on) {
  adc.select(on);
}
bool rdy_low(void*) {
  return adc.rdy_low(now_ticks());
}
void stepper_port(void*, uint8_t v) {
  board.motors.write(v);
}
bool home_switch(void*) {
  return false;
}
bool pwm_capture(void*, uint8_t axis, fw::pwm_period* out) {
  constexpr uint32_t period = 1000;  // 1 kHz (ADXL202 with RSET = 125 kOhm: T2 = 1 ms)
  const uint8_t a = axis & 1u;
  const uint32_t t = now_ticks();
  if (t - board.pwm_next[a] < period) return false;
  board.pwm_next[a] = t;
  out->high_ticks = 400;
  out->period_ticks = period;
  return true;
}
// QEMU's CMSDK UART holds one received byte: it is the span, kept until the core took it.
uint8_t rx_held = 0;
bool rx_holding = false;
size_t uart_read(void*, size_t taken, const volatile uint8_t** at) {
  if (taken != 0) rx_holding = false;
  if (!rx_holding && (uart0().state & 2u) != 0) {
    rx_held = static_cast<uint8_t>(uart0().data);
    rx_holding = true;
  }
  *at = &rx_held;
  return rx_holding ? 1 : 0;
}
size_t uart_write(void*, const uint8_t* bytes, size_t n) {
  size_t i = 0;
  for (; i < n && (uart0().state & 1u) == 0; ++i) uart0().data = bytes[i];
  return i;
}
uint32_t ticks(void*) {
  return now_ticks();
}
void nothing(void*) {}
uint16_t stack_unknown(void*) {
  return 0xFFFF;
}
uint8_t no_clock_faults(void*) {
  return 0;
}

// No step timer, no interrupts, no non-volatile store: the core works from its main loop.
constexpr fw::hal_ops ops = {
    spi_transfer,    spi_select, rdy_low, stepper_port, home_switch, pwm_capture,
    uart_read,       uart_write, ticks,   nothing,      nothing,     stack_unknown,
    no_clock_faults, nullptr,    nullptr, nullptr,      nullptr};
constexpr fw::hal hal{&ops, nullptr, tick_hz, false};
constinit fw::device dev(hal, fw::board_facts{0x51AB0001u, ad7739::mclk_hz_nominal,
                                              protocol::board_kind::qemu});

}  // namespace

int main() {
  uart0().bauddiv = cpu_hz / 115200;
  uart0().ctrl = 3u;
  systick().rvr = 0xFFFFFFu;
  systick().cvr = 0;
  systick().csr = 5u;  // enable, processor clock, no interrupt
  board.last_cvr = systick().cvr & 0xFFFFFFu;
  dev.boot({static_cast<uint8_t>(protocol::reset_cause::power_on), 1});
  for (;;) dev.poll();
}
