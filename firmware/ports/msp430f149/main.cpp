/// \file
/// \brief The MSP430F149 image (the paper's MCU): the firmware core with a HAL on the chip's
/// registers (docs/HARDWARE.md has the wiring and the pin map).
///   XT2 8 MHz -> MCLK, SMCLK; LFXT1 32 768 Hz -> ACLK.
///   USART0: UART 115200 8N1 to the PC (P3.4 TXD, P3.5 RXD), received bytes by interrupt.
///   USART1: SPI master, mode 3, 4 MHz, to the AD7739 (P5.1 SIMO, P5.2 SOMI, P5.3 UCLK);
///           P5.0 = AD7739 /CS; P2.0 = AD7739 /RDY; P2.1 = home switch (low = closed).
///   Timer_A: ACLK, continuous, overflow interrupt -> 32-bit ticks at 32 768 Hz.
///   Timer_B: SMCLK/8 = 1 MHz, capture on both edges of TB1 (P4.1, ADXL202 XOUT) and TB2
///            (P4.2, YOUT) -> high time and period of each duty cycle.
///   P6: stepper port (P6.0-3 motor 0, P6.4-7 motor 1) to two ULN2003 drivers.
///   Watchdog: ACLK, 1 s.
#include <stddef.h>
#include <stdint.h>

#include "firmware/core/device.hpp"
// Last: msp430.h defines one-letter macros (N, V, C, Z: the status register's bits).
#include <msp430.h>

namespace {

using namespace gyroflip;

// C++20 deprecates compound assignment to volatile; these say what is meant.
template <class Reg, class Mask>
void set_bits(Reg& reg, Mask mask) {
  reg = static_cast<Reg>(reg | mask);
}
template <class Reg, class Mask>
void clear_bits(Reg& reg, Mask mask) {
  reg = static_cast<Reg>(reg & ~mask);
}

void enable_interrupts() {
  __asm__ volatile("nop\n eint\n nop" ::: "memory");
}
void disable_interrupts() {
  __asm__ volatile("dint\n nop" ::: "memory");
}

// Interrupt-side state (the only data shared with ISRs; each read under dint where torn).
volatile uint16_t tick_overflows = 0;
constexpr uint8_t rx_size = 64;  // > 5 ms of 115200 b/s: the longest poll (a RAW frame's CRC)
volatile uint8_t rx_buf[rx_size];
volatile uint8_t rx_head = 0, rx_tail = 0;
struct pwm_axis {
  uint16_t last_rise = 0;
  uint16_t high = 0;
  bool have_rise = false;
  bool ready = false;
  uint16_t out_high = 0;
  uint16_t out_period = 0;
};
volatile pwm_axis pwm_axes[2];

void pwm_edge(uint8_t a, uint16_t t, bool rising) {
  volatile pwm_axis& s = pwm_axes[a];
  if (!rising) {
    s.high = static_cast<uint16_t>(t - s.last_rise);
    return;
  }
  if (s.have_rise) {
    s.out_high = s.high;
    s.out_period = static_cast<uint16_t>(t - s.last_rise);
    s.ready = true;
  }
  s.last_rise = t;
  s.have_rise = true;
}

uint32_t now_ticks() {
  uint16_t hi = 0;
  uint16_t lo = 0;
  do {
    hi = tick_overflows;
    lo = TAR;
  } while (hi != tick_overflows);
  return (static_cast<uint32_t>(hi) << 16) | lo;
}

// A byte takes 16 MCLK cycles at SMCLK / 2; a flag that has not come after spi_guard turns of
// its wait loop (thousands of cycles) never will: a USART fault, reported as a bus error without
// holding the boot (or the watchdog) for long.
constexpr uint16_t spi_guard = 256;

fw::status spi_transfer(void*, const uint8_t* tx, uint8_t* rx, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    uint16_t guard = 0;
    while ((IFG2 & UTXIFG1) == 0)
      if (++guard == spi_guard) return fw::status::bus_error;
    clear_bits(IFG2, URXIFG1);
    U1TXBUF = tx[i];
    guard = 0;
    while ((IFG2 & URXIFG1) == 0)
      if (++guard == spi_guard) return fw::status::bus_error;
    rx[i] = U1RXBUF;
  }
  return fw::status::ok;
}
void spi_select(void*, bool on) {
  if (on)
    clear_bits(P5OUT, 0x01u);
  else
    set_bits(P5OUT, 0x01u);
}
bool rdy_low(void*) {
  return (P2IN & 0x01u) == 0;
}
void stepper_port(void*, uint8_t v) {
  P6OUT = v;
}
bool home_switch(void*) {
  return (P2IN & 0x02u) == 0;
}
bool pwm_capture(void*, uint8_t axis, fw::pwm_period* out) {
  volatile pwm_axis& s = pwm_axes[axis & 1u];
  disable_interrupts();
  const bool ready = s.ready;
  out->high_ticks = s.out_high;
  out->period_ticks = s.out_period;
  s.ready = false;
  enable_interrupts();
  return ready;
}
bool uart_read(void*, uint8_t* b) {
  if (rx_tail == rx_head) return false;
  *b = rx_buf[rx_tail];
  rx_tail = static_cast<uint8_t>((rx_tail + 1u) % rx_size);
  return true;
}
bool uart_write(void*, uint8_t b) {
  if ((IFG1 & UTXIFG0) == 0) return false;
  U0TXBUF = b;
  return true;
}
uint32_t ticks(void*) {
  return now_ticks();
}
void watchdog_kick(void*) {
  WDTCTL = WDTPW | WDTCNTCL | WDTSSEL;
}
void busy_wait(void*) {}

constexpr fw::hal_ops ops = {spi_transfer, spi_select,    rdy_low,   stepper_port,
                             home_switch,  pwm_capture,   uart_read, uart_write,
                             ticks,        watchdog_kick, busy_wait};
constexpr fw::hal hal{&ops, nullptr, 32768};
// Constant-initialised: no constructor runs at start-up (startup.cpp).
constinit fw::device dev(hal, fw::board_facts{0x0F149001u, ad7739::mclk_hz_nominal});

void init_clocks() {
  clear_bits(BCSCTL1, XT2OFF);
  for (uint16_t i = 0; i < 1000; ++i) {  // wait for the crystals (bounded: DCO if absent)
    clear_bits(IFG1, OFIFG);
    for (volatile uint16_t d = 0; d < 255; d = static_cast<uint16_t>(d + 1)) {
    }
    if ((IFG1 & OFIFG) == 0) {
      BCSCTL2 = SELM_2 | SELS;  // MCLK = SMCLK = XT2 (8 MHz)
      return;
    }
  }
}

void init_peripherals() {
  P6OUT = 0;
  P6DIR = 0xFF;                // stepper port
  P5OUT = 0x01;                // /CS high
  P5DIR = 0x01 | 0x02 | 0x08;  // /CS, SIMO1, UCLK1 out
  P5SEL = 0x0E;                // SIMO1, SOMI1, UCLK1
  P2DIR = 0x00;                // /RDY, home switch in
  P3SEL = 0x30;                // UTXD0, URXD0
  P4SEL = 0x06;                // TB1, TB2 capture inputs
  // USART0: UART 115200 from SMCLK 8 MHz: 69 + modulation 0xAA (8e6 / 115200 = 69.44).
  U0CTL = CHAR | SWRST;
  U0TCTL = SSEL1;
  U0BR0 = 69;
  U0BR1 = 0;
  U0MCTL = 0xAA;
  set_bits(ME1, UTXE0 | URXE0);
  clear_bits(U0CTL, SWRST);
  set_bits(IE1, URXIE0);
  // USART1: SPI master, CKPL = 1 with CKPH = 0 (the AD7739's mode 3), SMCLK / 2 = 4 MHz.
  U1CTL = CHAR | SYNC | MM | SWRST;
  U1TCTL = CKPL | SSEL1 | STC;
  U1BR0 = 2;
  U1BR1 = 0;
  U1MCTL = 0;
  set_bits(ME2, USPIE1);
  clear_bits(U1CTL, SWRST);
  // Timer_A: ACLK continuous, overflow interrupt (the tick counter's high word).
  TACTL = TASSEL_1 | MC_2 | TAIE;
  // Timer_B: SMCLK / 8, continuous; TB1 and TB2 capture both edges.
  TBCTL = TBSSEL_2 | ID_3 | MC_2;
  TBCCTL1 = CM_3 | SCS | CAP | CCIE;
  TBCCTL2 = CM_3 | SCS | CAP | CCIE;
}

}  // namespace

extern "C" {

__attribute__((interrupt(TIMERA1_VECTOR))) void isr_timer_a1() {
  if (TAIV == TAIV_TAIFG) tick_overflows = static_cast<uint16_t>(tick_overflows + 1);
}

__attribute__((interrupt(TIMERB1_VECTOR))) void isr_timer_b1() {
  switch (TBIV) {
    case TBIV_TBCCR1:
      pwm_edge(0, TBCCR1, (TBCCTL1 & CCI) != 0);
      break;
    case TBIV_TBCCR2:
      pwm_edge(1, TBCCR2, (TBCCTL2 & CCI) != 0);
      break;
    default:
      break;
  }
}

__attribute__((interrupt(USART0RX_VECTOR))) void isr_usart0_rx() {
  const uint8_t b = U0RXBUF;
  const uint8_t next = static_cast<uint8_t>((rx_head + 1u) % rx_size);
  if (next != rx_tail) {  // full: the byte is lost, and the frame's CRC will say so
    rx_buf[rx_head] = b;
    rx_head = next;
  }
}

// The entry point startup.cpp calls (freestanding: clang does not treat `main` specially for
// msp430 and would mangle it).
void firmware_main() {
  init_clocks();  // the watchdog is held since the reset handler
  init_peripherals();
  WDTCTL = WDTPW | WDTCNTCL | WDTSSEL;
  enable_interrupts();
  dev.boot();
  for (;;) dev.poll();
}

}  // extern "C"
