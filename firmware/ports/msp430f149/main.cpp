/// \file
/// \brief The MSP430F149 image (the paper's MCU): the firmware core with a HAL on the chip's
/// registers (docs/HARDWARE.md has the wiring, the pin map and the clock choice).
///   XT2 5.5296 MHz -> MCLK, SMCLK (baud-exact: 115200 x 48; within the F149's frequency limit
///   at 3.3 V, docs/HARDWARE.md "Clocks and supply"); LFXT1 32 768 Hz -> ACLK.
///   USART0: UART 115200 8N1 to the PC (P3.4 TXD, P3.5 RXD), both directions by interrupt.
///   USART1: SPI master, mode 3, SMCLK / 2 = 2.76 MHz, to the AD7739 (P5.1 SIMO, P5.2 SOMI,
///           P5.3 UCLK); P5.0 = AD7739 /CS; P2.0 = AD7739 /RDY; P2.1 = home switch (low = closed).
///   Timer_A: ACLK, continuous, overflow interrupt -> 32-bit ticks at 32 768 Hz.
///   Timer_B: SMCLK/8 = 691.2 kHz, capture on both edges of TB1 (P4.1, ADXL202 XOUT) and TB2
///            (P4.2, YOUT) -> high time and period of each duty cycle.
///   P6: stepper port (P6.0-3 motor 0, P6.4-7 motor 1) to two ULN2003 drivers.
///   Watchdog: ACLK, 1 s, fed by the core only while its sequencer keeps its deadlines.
#include <stddef.h>
#include <stdint.h>

#include "firmware/core/device.hpp"
// Last: msp430.h defines one-letter macros (N, V, C, Z: the status register's bits).
#include <msp430.h>

namespace {

using namespace gyroflip;

constexpr uint32_t xt2_hz = 5529600;  // docs/HARDWARE.md, "Clocks and supply"
constexpr uint16_t uart_divider = xt2_hz / 115200;
static_assert(uart_divider * 115200u == xt2_hz, "a baud-exact crystal: no modulation needed");

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
volatile uint8_t osc_faults = 0;  // protocol::clock_fault bits the NMI saw
constexpr uint8_t rx_size = 64;   // > 5 ms of wire bytes at 115200 b/s: the longest poll
volatile uint8_t rx_buf[rx_size];
volatile uint8_t rx_head = 0, rx_tail = 0;
constexpr uint8_t tx_size = 32;  // 2.8 ms of line: the UART keeps sending through a long poll
volatile uint8_t tx_buf[tx_size];
volatile uint8_t tx_head = 0, tx_tail = 0;
volatile bool tx_idle = true;  // the USART's transmit buffer is empty and nothing is queued
struct pwm_axis {
  uint16_t last_rise = 0;
  uint16_t high = 0;
  bool have_rise = false;
  bool ready = false;
  uint16_t out_high = 0;
  uint16_t out_period = 0;
};
volatile pwm_axis pwm_axes[2];

// Kept through a reset that does not remove power (RAM is not cleared by the start-up): the boot
// counter and a magic word that tells a power-up (random RAM) from a reset.
constexpr uint16_t retained_magic = 0x6F1A;
__attribute__((section(".noinit"))) uint16_t retained_check;
__attribute__((section(".noinit"))) uint16_t retained_boots;

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

// TAR counts ACLK, asynchronous to the CPU's MCLK: a read while it changes may return a mix of
// the old and the new count. The user's guide's remedy (SLAU049, §11.2.1): read it several
// times and take the majority.
uint16_t read_tar() {
  for (;;) {
    const uint16_t a = TAR, b = TAR, c = TAR;
    if (a == b || a == c) return a;
    if (b == c) return b;
  }
}

// The 32-bit tick: the overflow count and TAR, read with interrupts off. When TAR has just
// wrapped but the overflow interrupt has not run yet (TAIFG still pending), the count is one
// short: a small TAR with TAIFG set belongs to the next overflow.
uint32_t now_ticks() {
  disable_interrupts();
  uint16_t hi = tick_overflows;
  const uint16_t lo = read_tar();
  if ((TACTL & TAIFG) != 0 && lo < 0x8000u) hi = static_cast<uint16_t>(hi + 1);
  enable_interrupts();
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
// Queues a wire byte for the transmit interrupt; the first byte after an idle line starts it.
bool uart_write(void*, uint8_t b) {
  disable_interrupts();
  bool queued = true;
  if (tx_idle) {
    tx_idle = false;
    U0TXBUF = b;
  } else {
    const uint8_t next = static_cast<uint8_t>((tx_head + 1u) % tx_size);
    if (next == tx_tail) {
      queued = false;
    } else {
      tx_buf[tx_head] = b;
      tx_head = next;
    }
  }
  enable_interrupts();
  return queued;
}
uint32_t ticks(void*) {
  return now_ticks();
}
void watchdog_kick(void*) {
  WDTCTL = WDTPW | WDTCNTCL | WDTSSEL;
}
void busy_wait(void*) {}

// The stack is painted at reset (startup.cpp paints it from the end of .noinit up to its own
// frame); the first unpainted word from below is the deepest the stack has reached.
extern "C" uint16_t __stack_paint_start[], __stack[];
constexpr uint16_t stack_paint = 0xA55A;
uint16_t stack_free(void*) {
  // Word by word between two linker symbols: counted, not compared as pointers.
  const uint16_t* p = __stack_paint_start;
  const uintptr_t words =
      (reinterpret_cast<uintptr_t>(__stack) - reinterpret_cast<uintptr_t>(p)) / 2;
  uintptr_t n = 0;
  while (n < words && p[n] == stack_paint) ++n;
  return static_cast<uint16_t>(2 * n);
}
uint8_t clock_faults(void*) {
  return osc_faults;
}

constexpr fw::hal_ops ops = {spi_transfer, spi_select, rdy_low,     stepper_port, home_switch,
                             pwm_capture,  uart_read,  uart_write,  ticks,        watchdog_kick,
                             busy_wait,    stack_free, clock_faults};
constexpr fw::hal hal{&ops, nullptr, 32768};
// Constant-initialised: no constructor runs at start-up (startup.cpp).
constinit fw::device dev(hal, fw::board_facts{0x0F149001u, ad7739::mclk_hz_nominal});

// Why this start: WDTIFG survives the PUC a watchdog overflow (or a watchdog key violation)
// causes and is cleared by a power-on reset (SLAU049 §10.2); the F149 has no flag for its reset
// pin, so a reset with the retained magic intact (RAM kept its contents: the power stayed) is
// taken as the pin, and one without it as a power-up.
fw::boot_info read_boot_info() {
  fw::boot_info b;
  const bool magic = retained_check == retained_magic;
  if ((IFG1 & WDTIFG) != 0) {
    b.reset_cause = static_cast<uint8_t>(protocol::reset_cause::watchdog);
  } else if (magic) {
    b.reset_cause = static_cast<uint8_t>(protocol::reset_cause::reset_pin);
  } else {
    b.reset_cause = static_cast<uint8_t>(protocol::reset_cause::power_on);
  }
  clear_bits(IFG1, WDTIFG);
  if (!magic) retained_boots = 0;
  retained_check = retained_magic;
  retained_boots = static_cast<uint16_t>(retained_boots + 1);
  b.boot_count = retained_boots;
  return b;
}

// XT2 to MCLK and SMCLK once the oscillator-fault flag stays clear (the crystal runs). A crystal
// that never starts leaves the chip on its DCO (~0.8 MHz, no exact baud rate): reported as a
// clock fault, and the device refuses to acquire.
void init_clocks() {
  clear_bits(BCSCTL1, XT2OFF);
  for (uint16_t i = 0; i < 1000; ++i) {
    clear_bits(IFG1, OFIFG);
    for (volatile uint16_t d = 0; d < 255; d = static_cast<uint16_t>(d + 1)) {
    }
    if ((IFG1 & OFIFG) == 0) {
      BCSCTL2 = SELM_2 | SELS;  // MCLK = SMCLK = XT2
      return;
    }
  }
  osc_faults = protocol::clock_xt2;
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
  // USART0: UART 115200 from SMCLK: an integer divider, no modulation.
  U0CTL = CHAR | SWRST;
  U0TCTL = SSEL1;
  U0BR0 = static_cast<uint8_t>(uart_divider & 0xFFu);
  U0BR1 = static_cast<uint8_t>(uart_divider >> 8);
  U0MCTL = 0;
  set_bits(ME1, UTXE0 | URXE0);
  clear_bits(U0CTL, SWRST);
  set_bits(IE1, URXIE0 | UTXIE0);
  // USART1: SPI master, CKPL = 1 with CKPH = 0 (the AD7739's mode 3), SMCLK / 2.
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
  // An oscillator fault later (XT2 stops) raises the NMI.
  clear_bits(IFG1, OFIFG);
  set_bits(IE1, OFIE);
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
  if (next != rx_tail) {  // full: the byte is lost, and the line code and CRC will say so
    rx_buf[rx_head] = b;
    rx_head = next;
  }
}

__attribute__((interrupt(USART0TX_VECTOR))) void isr_usart0_tx() {
  if (tx_tail == tx_head) {
    tx_idle = true;
    return;
  }
  U0TXBUF = tx_buf[tx_tail];
  tx_tail = static_cast<uint8_t>((tx_tail + 1u) % tx_size);
}

// An oscillator fault (OFIFG with OFIE): the hardware has switched MCLK to the DCO. Noted for
// the core, which stops acquiring and reports it; OFIE is cleared by the NMI itself.
__attribute__((interrupt(NMI_VECTOR))) void isr_nmi() {
  if ((IFG1 & OFIFG) != 0) osc_faults = static_cast<uint8_t>(osc_faults | protocol::clock_xt2);
}

// The entry point startup.cpp calls (freestanding: clang does not treat `main` specially for
// msp430 and would mangle it).
void firmware_main() {
  const fw::boot_info boot = read_boot_info();
  init_clocks();  // the watchdog is held since the reset handler
  init_peripherals();
  WDTCTL = WDTPW | WDTCNTCL | WDTSSEL;
  enable_interrupts();
  dev.boot(boot);
  for (;;) dev.poll();
}

}  // extern "C"
