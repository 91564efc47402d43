/// \file
/// \brief The MSP430F149 image (the paper's MCU): the firmware core with a HAL on the chip's
/// registers (docs/HARDWARE.md has the wiring, the pin map and the clock choice).
///   XT2 5.5296 MHz -> MCLK, SMCLK (baud-exact: 115200 x 48; within the F149's frequency limit
///   at 3.3 V, docs/HARDWARE.md "Clocks and supply"); LFXT1 32 768 Hz -> ACLK.
///   USART0: UART 115200 8N1 to the PC (P3.4 TXD, P3.5 RXD), both directions by interrupt.
///   USART1: SPI master, mode 3, SMCLK / 2 = 2.76 MHz, to the AD7739 (P5.1 SIMO, P5.2 SOMI,
///           P5.3 UCLK); P5.0 = AD7739 /CS; P5.4 = AD7739 /RESET; P2.0 = AD7739 /RDY (falling
///           edge: the conversion's interrupt); P2.1 = home switch (low = closed).
///   Timer_A: ACLK, continuous; overflow -> 32-bit ticks at 32 768 Hz; CCR1 compare -> the
///            stepper's step instants.
///   Timer_B: SMCLK/8 = 691.2 kHz, capture on both edges of TB1 (P4.1, ADXL202 XOUT) and TB2
///            (P4.2, YOUT) -> high time and period of each duty cycle.
///   P6: stepper port (P6.0-3 motor 0, P6.4-7 motor 1) to two ULN2003 drivers.
///   Every other pin: an output driven low (the F149 has no internal pull resistors).
///   Information flash: segment B (0x1000) the board's serial, segment A (0x1080) the dN in
///   force (firmware/core/nv_record.hpp).
///   Watchdog: ACLK, 1 s, fed by the core only while its sequencer keeps its deadlines.
/// Built with GYROFLIP_F149_SIM, the same image runs on mspdebug's simulator with stand-ins for
/// what it lacks (sim_board.hpp; tests/firmware/test_msp430_sim.cpp).
#include <stddef.h>
#include <stdint.h>

#include "firmware/core/device.hpp"
#include "firmware/ports/msp430f149/limits.hpp"
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
// Interrupts off, and whether they were on: the interrupt handlers call functions that the main
// loop calls too (the tick counter), and must not switch interrupts on inside a handler.
bool interrupts_off() {
  uint16_t sr = 0;
  __asm__ volatile("mov r2, %0" : "=r"(sr));
  disable_interrupts();
  return (sr & GIE) != 0;
}
void interrupts_restore(bool were_on) {
  if (were_on) enable_interrupts();
}

// Interrupt-side state (the only data shared with ISRs; each read under dint where torn).
volatile uint16_t tick_overflows = 0;
volatile uint8_t osc_faults = 0;  // protocol::clock_fault bits the NMI saw
// The UART's receive queue: 96 bytes hold 8.3 ms of line, more than the main loop's longest
// pass (commands behind bursts at the ramps' tops at the board's top rate, limits.hpp:
// docs/PERFORMANCE.md, "Timing on the chip"). Indices wrap by comparison (no division in the
// interrupt).
constexpr uint8_t rx_size = 96;
constexpr uint8_t rx_next(uint8_t i) {
  return static_cast<uint8_t>(i + 1u == rx_size ? 0u : i + 1u);
}
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
// counter, the running boot's counters (INFO prev_next_seq, prev_dwells; device::queue writes
// them through boot_info::keep), and a check that tells a power-up (random RAM) from a reset: a
// 16-bit magic and the count's complement, 2^-32 for random RAM to pass. Every access to the
// check goes through fw::shared/share (volatile): the compiler may not assume these start at
// zero (as C++ says a static does) and shrink them: clang 14 turned a plain 16-bit check word
// into a 1-byte flag that random RAM passed 255 times in 256.
struct retained_words {
  uint16_t magic;
  uint16_t boots;
  uint16_t boots_inverse;
  fw::retained_counters counters;
};
constexpr uint16_t retained_magic = 0x6F1A;
__attribute__((section(".noinit"))) retained_words retained;

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
// short: a small TAR with TAIFG set belongs to the next overflow. Callable from a handler.
uint32_t now_ticks() {
  const bool on = interrupts_off();
  uint16_t hi = tick_overflows;
  const uint16_t lo = read_tar();
  if ((TACTL & TAIFG) != 0 && lo < 0x8000u) hi = static_cast<uint16_t>(hi + 1);
  interrupts_restore(on);
  return (static_cast<uint32_t>(hi) << 16) | lo;
}

// Bytes the USART received (its interrupt; the simulator's line stand-in too).
void rx_byte(uint8_t b) {
  const uint8_t next = rx_next(rx_head);
  if (next != rx_tail) {  // full: the byte is lost, and the line code and CRC will say so
    rx_buf[rx_head] = b;
    rx_head = next;
  }
}

void tx_next();

}  // namespace

#if GYROFLIP_F149_SIM
#include "firmware/ports/msp430f149/sim_board.hpp"
#endif

namespace {

// The USART's transmit buffer: the first byte after an idle line, and each byte its interrupt
// asks for.
void tx_load(uint8_t b) {
#if GYROFLIP_F149_SIM
  sim::line_load(b);
#else
  U0TXBUF = b;
#endif
}
void tx_next() {
  if (tx_tail == tx_head) {
    tx_idle = true;
    return;
  }
  tx_load(tx_buf[tx_tail]);
  tx_tail = static_cast<uint8_t>((tx_tail + 1u) % tx_size);
}

// A byte takes 16 MCLK cycles at SMCLK / 2; a flag that has not come after spi_guard turns of
// its wait loop (thousands of cycles) never will: a USART fault, reported as a bus error without
// holding the boot (or the watchdog) for long.
constexpr uint16_t spi_guard = 256;

fw::status spi_transfer(void*, const uint8_t* tx, uint8_t* rx, size_t n) {
#if GYROFLIP_F149_SIM
  static_cast<void>(spi_guard);
  const uint16_t t0 = sim::tbr();
  sim::spi_from = t0;
  for (size_t i = 0; i < n; ++i) {
    sim::spi_bytes = static_cast<uint8_t>(i + 1);
    rx[i] = sim::adc_byte(tx[i]);
  }
  sim::spi_bytes = 0;
  // The stand-in's time out, the board's SPI time in (sim_board.hpp).
  sim::stub_counts = static_cast<uint16_t>(sim::stub_counts + (sim::tbr() - t0) -
                                           n * sim::board_spi_counts_per_byte);
  return fw::status::ok;
#else
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
#endif
}
void spi_select(void*, bool on) {
#if GYROFLIP_F149_SIM
  sim::adc_select(on);
#endif
  if (on)
    clear_bits(P5OUT, 0x01u);
  else
    set_bits(P5OUT, 0x01u);
}
bool rdy_low(void*) {
#if GYROFLIP_F149_SIM
  return sim::adc_rdy_low();
#else
  return (P2IN & 0x01u) == 0;
#endif
}
void stepper_port(void*, uint8_t v) {
  P6OUT = v;
#if GYROFLIP_F149_SIM
  sim::port_written(v);
#endif
}
bool home_switch(void*) {
  return (P2IN & 0x02u) == 0;
}
bool pwm_capture(void*, uint8_t axis, fw::pwm_period* out) {
  volatile pwm_axis& s = pwm_axes[axis & 1u];
  const bool on = interrupts_off();  // and back as they were: a caller may hold them off
  const bool ready = s.ready;
  out->high_ticks = s.out_high;
  out->period_ticks = s.out_period;
  s.ready = false;
  interrupts_restore(on);
  return ready;
}
// The received bytes in place (hal_ops::uart_read): frees what the core read of the last span,
// then the bytes from the queue's tail to its head, or to its end when the head has wrapped.
// Nothing is held off: the interrupt only writes at the head and moves it, one byte-wide store.
size_t uart_read(void*, size_t taken, const volatile uint8_t** at) {
  const auto tail = static_cast<uint8_t>(rx_tail + taken);
  const uint8_t from = tail == rx_size ? uint8_t{0} : tail;  // a span never passes the end
  rx_tail = from;
  const uint8_t head = rx_head;
  *at = rx_buf + from;
  return head >= from ? size_t{head} - from : size_t{rx_size} - from;
}
// Queues wire bytes for the transmit interrupt, then starts it when the line was idle. The
// queue is filled with interrupts on (the interrupt only reads at the tail); they are off only
// to start an idle line, and back as they were after (a caller may hold them off).
size_t uart_write(void*, const uint8_t* bytes, size_t n) {
  uint8_t head = tx_head;
  const uint8_t tail = tx_tail;  // may move on meanwhile: only more room
  size_t i = 0;
  for (; i < n; ++i) {
    const auto next = static_cast<uint8_t>((head + 1u) % tx_size);
    if (next == tail) break;
    tx_buf[head] = bytes[i];
    head = next;
  }
  tx_head = head;
  const bool on = interrupts_off();
  if (tx_idle && tx_tail != tx_head) {
    tx_idle = false;
    tx_next();
  }
  interrupts_restore(on);
  return i;
}
uint32_t ticks(void*) {
  return now_ticks();
}
void watchdog_kick(void*) {
  WDTCTL = WDTPW | WDTCNTCL | WDTSSEL;
#if GYROFLIP_F149_SIM
  sim::watchdog_kicked(now_ticks());
#endif
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

// The step timer: Timer_A's CCR1 compares with the low 16 bits of the due tick (a step is never
// more than 65 535 ticks ahead: device::handle refuses a slower start rate). A due tick that has
// passed (or passes while it is written) sets the interrupt flag at once.
void step_timer(void*, bool arm, uint32_t due) {
  const bool on = interrupts_off();
  if (!arm) {
    TACCTL1 = 0;
  } else {
    TACCR1 = static_cast<uint16_t>(due);
    TACCTL1 = CCIE;
    if (static_cast<int32_t>(now_ticks() - due) >= 0) TACCTL1 = CCIE | CCIFG;
  }
  interrupts_restore(on);
}

// Critical sections of the core (not nested): interrupts off, and back as they were.
bool critical_was_on = false;
void critical(void*, bool enter) {
  if (enter) {
    critical_was_on = interrupts_off();
  } else {
    interrupts_restore(critical_was_on);
  }
}

// The information flash: segment B at 0x1000 (the board's serial, written by the lab), segment A
// at 0x1080 (the dN in force), 128 bytes each (SLAS272H, memory map; SLAU049 §5).
uint8_t* segment(uint8_t id) {
  return reinterpret_cast<uint8_t*>(id == fw::nv_board ? 0x1000u : 0x1080u);
}
bool nv_read(void*, uint8_t id, uint8_t* buf, size_t n) {
  if (id > fw::nv_delta_n || n > 128) return false;
  const volatile uint8_t* at = segment(id);
  for (size_t i = 0; i < n; ++i) buf[i] = at[i];
  return true;
}
// Erase, then byte writes (SLAU049 §5.3: the flash timing generator at 257-476 kHz: MCLK / 13 =
// 425 kHz; a segment erase takes 4819 of its cycles, 11.3 ms, a byte 35, with the CPU held when
// the code runs from flash; interrupts off throughout: the vectors are in flash).
bool nv_write(void*, uint8_t id, const uint8_t* buf, size_t n) {
  if (id > fw::nv_delta_n || n > 128) return false;
  volatile uint8_t* at = segment(id);
  WDTCTL = WDTPW | WDTCNTCL | WDTSSEL;
  const bool on = interrupts_off();
  FCTL2 = FWKEY | FSSEL_1 | 12u;
  FCTL3 = FWKEY;          // unlock
  FCTL1 = FWKEY | ERASE;  // segment erase, started by a dummy write into it
  at[0] = 0;
  FCTL1 = FWKEY | WRT;
  for (size_t i = 0; i < n; ++i) at[i] = buf[i];
  FCTL1 = FWKEY;
  FCTL3 = FWKEY | LOCK;
  interrupts_restore(on);
  return true;
}

constexpr fw::hal_ops ops = {spi_transfer, spi_select, rdy_low,      stepper_port, home_switch,
                             pwm_capture,  uart_read,  uart_write,   ticks,        watchdog_kick,
                             busy_wait,    stack_free, clock_faults, step_timer,   critical,
                             nv_read,      nv_write};
// The port calls device::on_rdy from the /RDY interrupt (PORT2, P2.0 falling edge).
constexpr fw::hal hal{&ops, nullptr, 32768, true};
// Constant-initialised: no constructor runs at start-up (startup.cpp). The serial 0 means "not
// programmed": a board's own is in its information flash (docs/HARDWARE.md, "Bring-up").
// The top step rate the board produces: limits.hpp (docs/PERFORMANCE.md, "Timing on the chip").
constinit fw::device dev(hal,
                         fw::board_facts{0, ad7739::mclk_hz_nominal, protocol::board_kind::hardware,
                                         fw::msp430f149::max_step_rate_sps, true});

// Why this start: WDTIFG survives the PUC a watchdog overflow (or a watchdog key violation)
// causes and is cleared by a power-on reset (SLAU049 §10.2); the F149 has no flag for its reset
// pin, so a reset with the retained check intact (RAM kept its contents: the power stayed) is
// taken as the pin, and one without it as a power-up. The previous boot's counters are valid
// only with the check intact.
fw::boot_info read_boot_info() {
  fw::boot_info b;
  using fw::share;
  using fw::shared;
  const uint16_t boots_before = shared(retained.boots);
  const bool kept = shared(retained.magic) == retained_magic &&
                    shared(retained.boots_inverse) == static_cast<uint16_t>(~boots_before);
  if ((IFG1 & WDTIFG) != 0) {
    b.reset_cause = static_cast<uint8_t>(protocol::reset_cause::watchdog);
  } else if (kept) {
    b.reset_cause = static_cast<uint8_t>(protocol::reset_cause::reset_pin);
  } else {
    b.reset_cause = static_cast<uint8_t>(protocol::reset_cause::power_on);
  }
  clear_bits(IFG1, WDTIFG);
  b.prev_valid = kept;
  if (kept) {
    b.prev.next_seq = shared(retained.counters.next_seq);
    b.prev.dwells = shared(retained.counters.dwells);
  }
  const uint16_t boots = kept ? static_cast<uint16_t>(boots_before + 1) : uint16_t{1};
  share(retained.boots, boots);
  share(retained.boots_inverse, static_cast<uint16_t>(~boots));
  share(retained.magic, retained_magic);
  b.boot_count = boots;
  b.keep = &retained.counters;
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

// Every pin: the used ones to their function, the others outputs driven low. The F149's port
// pins have no pull resistors (SLAU049 §9: "unused I/O pins should be configured as I/O function,
// output direction, and left unconnected"): a floating input draws current and can oscillate.
void init_pins() {
  P1OUT = 0;
  P1DIR = 0xFF;  // unused (P1.1 is the BSL's transmit pin: an output either way)
  P2OUT = 0;
  P2DIR = static_cast<uint8_t>(~(0x01u | 0x02u | 0x04u));  // in: /RDY, home switch, BSL receive
  P3OUT = 0;
  P3DIR = static_cast<uint8_t>(~0x20u);  // URXD0 in, the rest (UTXD0 included) out
  P3SEL = 0x30;                          // UTXD0, URXD0
  P4OUT = 0;
  P4DIR = static_cast<uint8_t>(~(0x02u | 0x04u));  // TB1, TB2 capture inputs
  P4SEL = 0x06;
  P5OUT = 0x01;  // /CS high; /RESET (P5.4) low: the AD7739 held in reset until init_adc
  P5DIR = static_cast<uint8_t>(~0x04u);  // SOMI1 in
  P5SEL = 0x0E;                          // SIMO1, SOMI1, UCLK1
  P6OUT = 0;
  P6DIR = 0xFF;  // stepper port
}

// The AD7739's /RESET: held low since init_pins, released here; the core's serial reset and its
// wait follow in device::boot.
void init_adc() {
  for (volatile uint16_t d = 0; d < 100; d = static_cast<uint16_t>(d + 1)) {
  }
  set_bits(P5OUT, 0x10u);
}

void init_peripherals() {
  init_pins();
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
  // Timer_A: ACLK continuous, overflow interrupt (the tick counter's high word); CCR1 is the
  // step timer.
  TACTL = TASSEL_1 | MC_2 | TAIE;
  // Timer_B: SMCLK / 8, continuous; TB1 and TB2 capture both edges.
  TBCTL = TBSSEL_2 | ID_3 | MC_2;
  TBCCTL1 = CM_3 | SCS | CAP | CCIE;
  TBCCTL2 = CM_3 | SCS | CAP | CCIE;
  // /RDY falling (P2.0): a conversion's result is ready.
  set_bits(P2IES, 0x01u);
  clear_bits(P2IFG, 0x01u);
  set_bits(P2IE, 0x01u);
  // An oscillator fault later (XT2 stops) raises the NMI.
  clear_bits(IFG1, OFIFG);
  set_bits(IE1, OFIE);
#if GYROFLIP_F149_SIM
  sim::init();
#endif
  init_adc();
}

}  // namespace

extern "C" {

// Timer_A's CCR1 (the step timer) and overflow.
__attribute__((interrupt(TIMERA1_VECTOR))) void isr_timer_a1() {
#if GYROFLIP_F149_SIM
  const uint16_t t0 = sim::isr_begin();
#endif
  switch (TAIV) {
    case TAIV_TACCR1: {
      const uint32_t now = now_ticks();
#if GYROFLIP_F149_SIM
      sim::step_due(now, TACCR1);
#endif
      uint32_t next = 0;
      if (dev.on_step_timer(now, &next)) {
        // The next step well ahead of the tick read at entry (the step's own work takes ~3
        // ticks): the compare alone, CCIE is still set. Else step_timer, which reads the clock
        // again and raises the flag at once when the instant has passed (~150 MCLK cycles more,
        // ~5 % of the CPU at 2 000 steps/s).
        if (static_cast<int32_t>(next - now) > 8) {
          TACCR1 = static_cast<uint16_t>(next);
        } else {
          step_timer(nullptr, true, next);
        }
      } else {
        TACCTL1 = 0;
      }
      break;
    }
    case TAIV_TAIFG:
      tick_overflows = static_cast<uint16_t>(tick_overflows + 1);
      break;
    default:
      break;
  }
#if GYROFLIP_F149_SIM
  sim::isr_end(t0);
#endif
}

// /RDY fell: the conversion's result is there; the core starts the next and reads it. With
// interrupts on again: its SPI transfers take ~1 000 MCLK cycles, longer than the UART's two
// bytes of buffering (960 cycles at 115 200 b/s), and the other handlers touch neither the bus
// nor the conversion's state; the next /RDY edge is a conversion time away.
__attribute__((interrupt(PORT2_VECTOR))) void isr_port2() {
  const bool rdy = (P2IFG & 0x01u) != 0;
  P2IFG = 0;
  if (!rdy) return;
  // The conversion times are 16-bit tick differences: TAR alone, no overflow count to combine.
  const uint16_t now = read_tar();
  enable_interrupts();
  dev.on_rdy(now);
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

// Timer_B's CCR0 and Timer_A's CCR0: unused on the board; on the simulator, the serial line's
// stand-in (a byte time) and the AD7739's (a conversion's end: /RDY falls).
__attribute__((interrupt(TIMERB0_VECTOR))) void isr_timer_b0() {
#if GYROFLIP_F149_SIM
  sim::line_tick();
#endif
}
#if GYROFLIP_F149_SIM
// The board's clock ratio (sim_board.hpp): a simulated timer's CCR0 on an unused vector.
__attribute__((interrupt(COMPARATORA_VECTOR))) void isr_sim_clock_ratio() {
  sim::steal();
}
#endif
__attribute__((interrupt(TIMERA0_VECTOR))) void isr_timer_a0() {
#if GYROFLIP_F149_SIM
  const uint16_t t0 = sim::isr_begin();
  if (sim::adc_conversion_done()) {
    const uint16_t now = read_tar();
    enable_interrupts();  // as isr_port2 on the board
    dev.on_rdy(now);
  }
  sim::isr_end(t0, sim::sl::w_adc_isr_max);
#endif
}

__attribute__((interrupt(USART0RX_VECTOR))) void isr_usart0_rx() {
  rx_byte(U0RXBUF);
}

__attribute__((interrupt(USART0TX_VECTOR))) void isr_usart0_tx() {
  tx_next();
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
#if GYROFLIP_F149_SIM
  // Measurements above the board's limit (sim_layout.hpp, rate_limit_addr); the board's own
  // limit unless the test asks.
  if (const uint16_t sps = sim::rate_limit_sps(); sps != 0) dev.set_max_step_rate_sps(sps);
#endif
  dev.boot(boot);
  for (;;) {
#if GYROFLIP_F149_SIM
    const uint16_t t0 = sim::poll_begin();
    dev.poll();
    sim::poll_end(t0, now_ticks());
    sim::steps_seen(dev.step_rebases());
#else
    dev.poll();
#endif
  }
}

}  // extern "C"
