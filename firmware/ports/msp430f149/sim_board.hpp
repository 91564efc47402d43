/// \file
/// \brief Stand-ins for what mspdebug's simulator lacks, for the MSP430F149 image built with
/// GYROFLIP_F149_SIM (main.cpp includes this in its anonymous namespace's file scope; nothing
/// here is in the shipped image). The simulator has a CPU, RAM, Timer_A-class timers and a
/// watchdog, and no USART, no port pins and no AD7739:
///  - the serial line: a second simulated timer at Timer_B's address runs from SMCLK / 8 as on
///    the board, and its CCR0 interrupt every `line_counts` (one byte at 115 200 b/s: 480 of the
///    board's MCLK cycles, 728 of the simulator's, see the clock ratio below) ends the byte being
///    sent (logged, and the USART transmit interrupt's work done) and delivers the next byte of the
///    host's script to the receive queue as the USART receive interrupt would;
///  - the AD7739: its SPI bytes are answered here (communications register, conversion-time and
///    mode writes, revision and dump-mode data reads), a conversion or a calibration step ends
///    at its start tick plus its conversion time in ticks (the driver's own formula), and
///    Timer_A's CCR0 interrupt at that tick stands for /RDY falling (PORT2 on the board);
///    mspdebug 0.22's timer decodes only CCR0 and CCR1 of a 3-register timer (simio_timer.c
///    compares the address with base + size instead of base + 2 size), and CCR1 is the step
///    timer;
///  - measurements: each main-loop pass and each Timer_A interrupt timed with Timer_B, the
///    stepper port's writes, conversions, watchdog kicks and the bytes sent, logged in
///    sim_layout.hpp's memory for the test.
///  - the board's clock ratio: the simulator's ACLK (the tick) is MCLK / 256 (mspdebug 0.22
///    simio.c, not configurable), the board's MCLK / 168.75 (5.5296 MHz / 32 768 Hz). A third
///    simulated timer (at 0x1C0, SMCLK / 8, its CCR0 on the Comparator_A vector) interrupts
///    every 1 024 cycles and takes 349 of every 1 024 from the firmware (87.25 of 256) in a busy
///    loop the firmware's interrupts preempt (they are served at once), so that it gets the
///    board's 168.75 cycles a tick: everything timed in ticks (steps, conversions, the line's
///    bytes) sees the board's CPU. Its cycles are left out of every measured figure.
#pragma once

#include "firmware/drivers/ad7739/convert.hpp"
#include "firmware/drivers/ad7739/regs.hpp"
#include "firmware/ports/msp430f149/sim_layout.hpp"

extern "C" __attribute__((noinline)) void sim_done();
extern "C" __attribute__((noinline)) void sim_done() {
  __asm__ volatile("" ::: "memory");
}

namespace sim {

namespace sl = gyroflip::fw::simboard;
namespace ad = gyroflip::ad7739;

inline volatile uint16_t* stats() {
  return reinterpret_cast<volatile uint16_t*>(sl::stats_addr);
}
inline uint32_t get32(uint8_t w) {
  return stats()[w] | (static_cast<uint32_t>(stats()[w + 1]) << 16);
}
inline void put32(uint8_t w, uint32_t v) {
  stats()[w] = static_cast<uint16_t>(v);
  stats()[w + 1] = static_cast<uint16_t>(v >> 16);
}
inline uint16_t tbr() {
  return TBR;
}

// Timer_B counts spent in the stand-ins (the line's interrupt, the AD7739's SPI answers):
// subtracted from the measured passes and interrupts, so that the figures are the firmware's
// own, with the board's SPI time (40 MCLK cycles a byte at SMCLK / 2 with the loop's overhead)
// added back.
uint16_t stub_counts = 0;
// Timer_B counts the clock-ratio stand-in took (written by its interrupt only).
volatile uint16_t stolen = 0;
// Counts not the firmware's own: the stand-ins' and the clock ratio's.
inline uint16_t away() {
  return static_cast<uint16_t>(stub_counts + stolen);
}
// The Timer_B counts the interrupts took (their spans, with ~4 counts of entry and return; a
// nested one inside the outer one's): the clock-ratio stand-in tells its own time from theirs.
volatile uint16_t isr_counts = 0;
uint8_t isr_depth = 0;
inline void isr_done(uint16_t span) {
  if (--isr_depth == 0) isr_counts = static_cast<uint16_t>(isr_counts + span + 4);
}
// One byte at 115 200 b/s: 480 board cycles, 480 x 256 / 168.75 = 728 simulator cycles.
constexpr uint16_t line_counts = 91;
constexpr uint16_t board_spi_counts_per_byte = 5;  // 40 MCLK cycles
// The SPI transfer in progress (main.cpp spi_transfer): since when, and bytes so far (0: none).
uint16_t spi_from = 0;
uint8_t spi_bytes = 0;

// ---- the serial line ---------------------------------------------------------------------
// The line's interrupt runs only while a byte moves (as the USART's do on the board): a byte
// being sent, or the host's script delivering an event; the main loop's pass starts it at an
// event's tick (poll_end).
bool tx_shifting = false;
bool line_on = false;
uint8_t tx_byte = 0;
uint16_t script_at = 0;  // offset of the next byte (or event header) in the script
uint16_t script_left = 0;
uint32_t script_tick = 0;

// The tick in an interrupt handler (the simulator's timer is synchronous: one read is enough).
inline uint32_t isr_ticks() {
  uint16_t hi = tick_overflows;
  const uint16_t lo = TAR;
  if ((TACTL & TAIFG) != 0 && lo < 0x8000u) hi = static_cast<uint16_t>(hi + 1);
  return (static_cast<uint32_t>(hi) << 16) | lo;
}

inline void line_start() {
  if (line_on) return;
  line_on = true;
  TBCCR0 = static_cast<uint16_t>(TBR + line_counts);
  TBCCTL0 = CCIE;
}

inline void line_load(uint8_t b) {
  tx_byte = b;
  tx_shifting = true;
  line_start();
}

inline const volatile uint16_t* script() {
  return reinterpret_cast<const volatile uint16_t*>(sl::script_addr);
}

// The next event's header (tick, length).
inline void next_event() {
  const uint16_t count = script()[0];
  if (stats()[sl::w_script_next] >= count) return;
  const uint16_t w = static_cast<uint16_t>(script_at / 2);
  script_tick = script()[w] | (static_cast<uint32_t>(script()[w + 1]) << 16);
  script_left = script()[w + 2];
  script_at = static_cast<uint16_t>(script_at + 6);
  stats()[sl::w_script_next] = static_cast<uint16_t>(stats()[sl::w_script_next] + 1);
}

inline bool event_due(uint32_t now) {
  return script_left != 0 && static_cast<int32_t>(now - script_tick) >= 0;
}

// One byte time (Timer_B's CCR0, 480 MCLK cycles): as little work as the USART's interrupts on
// the board (the transmit log is a store and an index; the figures go to the stats words at the
// end of each main-loop pass), so that the main loop's passes are measured as on the board.
uint16_t tx_n = 0;
uint8_t rx_fill_max = 0;
uint16_t rx_lost = 0;
inline void line_tick() {
  const uint16_t entry = tbr();
  ++isr_depth;
  // The next byte time; one that has passed (another interrupt held this one back longer than a
  // byte) is taken from now: the line's bytes simply come later, as a UART's would.
  const uint16_t next = static_cast<uint16_t>(TBCCR0 + line_counts);
  const uint16_t now = TBR;
  TBCCR0 = static_cast<int16_t>(static_cast<uint16_t>(next - now)) > 0
               ? next
               : static_cast<uint16_t>(now + line_counts);
  if (tx_shifting) {
    tx_shifting = false;
    if (tx_n < sl::tx_log_cap) reinterpret_cast<uint8_t*>(sl::tx_log_addr)[tx_n++] = tx_byte;
    tx_next();  // the USART's transmit interrupt: the next byte, if any (line_load)
  }
  const bool rx = event_due(isr_ticks());
  if (rx) {
    const uint8_t fill =
        static_cast<uint8_t>(rx_head >= rx_tail ? rx_head - rx_tail : rx_head + rx_size - rx_tail);
    if (fill + 1u >= rx_size) ++rx_lost;
    if (fill + 1u > rx_fill_max) rx_fill_max = static_cast<uint8_t>(fill + 1u);
    rx_byte(reinterpret_cast<const uint8_t*>(sl::script_addr)[script_at++]);
    if (--script_left == 0) {
      script_at = static_cast<uint16_t>((script_at + 1u) & ~1u);
      next_event();
    }
  }
  if (!tx_shifting && !rx) {
    line_on = false;
    TBCCTL0 = 0;
  }
  // The board's USART interrupts do this work in ~4 counts (30 cycles) a byte.
  const uint16_t spent = static_cast<uint16_t>(tbr() - entry);
  stub_counts = static_cast<uint16_t>(stub_counts + (spent > 4 ? spent - 4 : 0) + 3);
  isr_done(spent);
}

// ---- the AD7739 ----------------------------------------------------------------------------
struct adc_model {
  bool expect_comm = true;
  uint8_t addr = 0;
  bool reading = false;
  uint8_t n = 0;  // bytes left in this access
  uint8_t k = 0;
  uint8_t out[4] = {};
  uint16_t conv_ticks[8] = {66, 66, 66, 66, 66, 66, 66, 66};
  uint8_t ready = 0;       // channels with an unread result (the /RDY line is low while any)
  bool cal_ready = false;  // a calibration step ended (/RDY low until the next mode write)
  bool busy = false;
  uint8_t busy_ch = 0;
  bool busy_convert = false;
  uint16_t log_at = 0;     // the conversion log's entry of the running conversion
  uint16_t result_at = 0;  // the entry of the conversion whose result waits to be read
  // The next code of each channel: the code of conversion `index` (sim_layout.hpp code_of),
  // kept by steps so that the stand-in divides nothing (its time counts as the firmware's).
  int32_t next_code[2] = {sl::code_of(0, 0), sl::code_of(1, 0)};
  uint8_t cycle[2] = {0, 0};
};
adc_model adc;

inline volatile uint32_t* conv_log() {
  return reinterpret_cast<volatile uint32_t*>(sl::conv_log_addr);
}

inline void adc_select(bool) {
  adc.expect_comm = true;
}

inline bool adc_rdy_low() {
  return adc.ready != 0 || adc.cal_ready;
}

// The last conversion's end, for the restart figure (w_restart_*).
struct restart_mark {
  bool waiting = false;
  uint16_t from = 0;  // Timer_B
  uint16_t stub = 0;  // stub_counts then
  uint32_t tick = 0;
};
restart_mark restart;

inline void adc_start(uint8_t ch, bool convert) {
  const uint32_t now = isr_ticks();
  if (convert && restart.waiting && now - restart.tick < 2u * adc.conv_ticks[ch]) {
    const uint16_t at = tbr();
    const uint16_t raw = static_cast<uint16_t>(at - restart.from);
    // The stand-in's time in this transfer so far out, the board's SPI bytes in.
    const uint16_t open =
        spi_bytes == 0
            ? 0
            : static_cast<uint16_t>(at - spi_from - spi_bytes * board_spi_counts_per_byte);
    const uint16_t stub = static_cast<uint16_t>(away() - restart.stub + open);
    const uint16_t own = raw > stub ? static_cast<uint16_t>(raw - stub) : 0;
    if (own > stats()[sl::w_restart_max]) stats()[sl::w_restart_max] = own;
    put32(sl::w_restart_sum_lo, get32(sl::w_restart_sum_lo) + own);
    stats()[sl::w_restarts] = static_cast<uint16_t>(stats()[sl::w_restarts] + 1);
  }
  restart.waiting = false;
  adc.busy = true;
  adc.busy_ch = ch;
  adc.busy_convert = convert;
  adc.cal_ready = false;  // a channel's result stays until it is read (or its next scaling time)
  TACCR0 = static_cast<uint16_t>(now + adc.conv_ticks[ch]);
  TACCTL0 = CCIE;
  if (!convert) return;
  const uint16_t c = stats()[sl::w_convs];
  adc.log_at = c;
  if (c < sl::conv_log_cap) {
    conv_log()[2 * c] = now;
    conv_log()[2 * c + 1] = 0;
    stats()[sl::w_convs] = static_cast<uint16_t>(c + 1);
  }
}

// Timer_A's CCR0: the running conversion (or calibration step) ends; /RDY falls.
inline bool adc_conversion_done() {
  TACCTL0 = 0;
  if (!adc.busy) return false;
  adc.busy = false;
  if (adc.busy_convert) {
    adc.ready = static_cast<uint8_t>(adc.ready | (1u << adc.busy_ch));
    adc.result_at = adc.log_at;
    restart = {true, tbr(), away(), isr_ticks()};
  } else {
    adc.cal_ready = true;  // no result: the data register keeps the last conversion's
  }
  return true;
}

inline void adc_commit(uint8_t v) {
  if (adc.addr >= ad::reg_conv_time && adc.addr < ad::reg_conv_time + 8) {
    const uint8_t ch = static_cast<uint8_t>(adc.addr - ad::reg_conv_time);
    const uint8_t fw = static_cast<uint8_t>(v & ad::conv_fw_mask);
    const uint32_t mclk =
        ad::conversion_mclk((v & ad::conv_chop) != 0, fw < ad::fw_min ? ad::fw_min : fw);
    // Ticks, rounded up (the core's mclk_to_ticks), in 32 bits: mclk < 2^15.
    adc.conv_ticks[ch] =
        static_cast<uint16_t>((mclk * 32768u + ad::mclk_hz_nominal - 1u) / ad::mclk_hz_nominal);
  }
  if (adc.addr >= ad::reg_mode && adc.addr < ad::reg_mode + 8) {
    const uint8_t ch = static_cast<uint8_t>(adc.addr - ad::reg_mode);
    const uint8_t md = static_cast<uint8_t>(v & ad::mode_md_mask);
    if (md == ad::mode_single) adc_start(ch, true);
    if (md == ad::mode_adc_zero_self_cal || md == ad::mode_adc_full_self_cal) adc_start(ch, false);
  }
}

inline uint8_t adc_byte(uint8_t in) {
  if (adc.expect_comm) {
    if (in == 0xFF) return 0xFF;  // the serial reset's ones
    adc.addr = static_cast<uint8_t>(in & 0x3Fu);
    adc.reading = (in & ad::comm_read) != 0;
    adc.expect_comm = false;
    adc.k = 0;
    adc.n = 1;
    if (adc.reading && adc.addr >= ad::reg_data && adc.addr < ad::reg_data + 8) {
      const uint8_t ch = static_cast<uint8_t>(adc.addr - ad::reg_data);
      const bool rdy = (adc.ready & (1u << ch)) != 0;
      const uint8_t k = ch & 1u;
      const uint32_t raw = static_cast<uint32_t>(adc.next_code[k] + ad::code_zero);
      adc.out[0] = static_cast<uint8_t>((ch << ad::chst_channel_shift) | (rdy ? ad::chst_rdy : 0u));
      adc.out[1] = static_cast<uint8_t>(raw >> 16);
      adc.out[2] = static_cast<uint8_t>(raw >> 8);
      adc.out[3] = static_cast<uint8_t>(raw);
      adc.n = 4;
      if (rdy) {
        adc.ready = static_cast<uint8_t>(adc.ready & ~(1u << ch));
        // The next conversion's code: code_of(ch, index + 1), by steps of 37 (gyro, 11 a cycle)
        // or 1 (temperature, 3 a cycle).
        const uint8_t period = k == 0 ? 11 : 3;
        if (++adc.cycle[k] == period) {
          adc.cycle[k] = 0;
          adc.next_code[k] = sl::code_of(k, 0);
        } else {
          adc.next_code[k] += k == 0 ? 37 : 1;
        }
        if (adc.result_at < sl::conv_log_cap) conv_log()[2 * adc.result_at + 1] = isr_ticks();
      }
    } else if (adc.reading) {
      adc.out[0] = adc.addr == ad::reg_revision ? sl::revision : 0;
    }
    return 0xFF;
  }
  uint8_t r = 0xFF;
  if (adc.reading) {
    r = adc.k < 4 ? adc.out[adc.k] : 0;
  } else if (adc.k == 0) {
    adc_commit(in);
  }
  ++adc.k;
  if (--adc.n == 0) adc.expect_comm = true;
  return r;
}

// ---- measurements ------------------------------------------------------------------------
uint8_t step_late = 0xFF;

inline void step_due(uint32_t now, uint16_t ccr) {
  const uint16_t t0 = tbr();
  const uint16_t late = static_cast<uint16_t>(static_cast<uint16_t>(now) - ccr);
  step_late = static_cast<uint8_t>(late > 0xFEu ? 0xFEu : late);
  if (late > stats()[sl::w_step_late_max] && late < 0x8000u) stats()[sl::w_step_late_max] = late;
  stub_counts = static_cast<uint16_t>(stub_counts + (tbr() - t0));
}

inline void port_written(uint8_t v) {
  const uint16_t t0 = tbr();
  const uint16_t n = stats()[sl::w_port_writes];
  if (n < sl::port_log_cap) {
    volatile uint8_t* e = reinterpret_cast<volatile uint8_t*>(sl::port_log_addr) + 4u * n;
    const uint16_t t = static_cast<uint16_t>(isr_ticks());
    e[0] = static_cast<uint8_t>(t);
    e[1] = static_cast<uint8_t>(t >> 8);
    e[2] = v;
    e[3] = step_late;
    stats()[sl::w_port_writes] = static_cast<uint16_t>(n + 1);
  }
  step_late = 0xFF;
  stub_counts = static_cast<uint16_t>(stub_counts + (tbr() - t0));
}

bool booted = false;
inline void watchdog_kicked(uint32_t now) {
  if (booted) {
    const uint32_t gap = now - get32(sl::w_wd_last_lo);
    if (gap > get32(sl::w_wd_gap_lo)) put32(sl::w_wd_gap_lo, gap);
  }
  put32(sl::w_wd_last_lo, now);
}

uint16_t isr_stub_at = 0;
inline uint16_t isr_begin() {
  isr_stub_at = away();
  ++isr_depth;
  return tbr();
}
inline void isr_end(uint16_t t0, uint8_t word = sl::w_isr_max) {
  const uint16_t dt = static_cast<uint16_t>(tbr() - t0);
  isr_done(dt);
  const uint16_t stub = static_cast<uint16_t>(away() - isr_stub_at);
  const uint16_t own = dt > stub ? static_cast<uint16_t>(dt - stub) : 0;
  if (own > stats()[word]) stats()[word] = own;
}

uint32_t poll_from = 0;
uint16_t poll_stub_at = 0;
inline uint16_t poll_begin() {
  booted = true;
  poll_from = isr_ticks();
  poll_stub_at = away();
  return tbr();
}

inline void poll_end(uint16_t t0, uint32_t now) {
  const uint16_t raw = static_cast<uint16_t>(tbr() - t0);
  const uint16_t stub = static_cast<uint16_t>(away() - poll_stub_at);
  const uint16_t dt = raw > stub ? static_cast<uint16_t>(raw - stub) : 0;
  stats()[sl::w_tx_bytes] = tx_n;
  stats()[sl::w_rx_lost] = rx_lost;
  stats()[sl::w_rx_max_fill] = rx_fill_max;
  put32(sl::w_polls_lo, get32(sl::w_polls_lo) + 1);
  if (dt > stats()[sl::w_poll_max]) {
    stats()[sl::w_poll_max] = dt;
    put32(sl::w_poll_max_at_lo, now);
    put32(sl::w_poll_max_from_lo, poll_from);
  }
  if (dt > sl::poll_limit) put32(sl::w_polls_over_lo, get32(sl::w_polls_over_lo) + 1);
  if (!line_on && event_due(now)) {
    const bool on = interrupts_off();
    line_start();
    interrupts_restore(on);
  }
  const uint32_t stop = script()[1] | (static_cast<uint32_t>(script()[2]) << 16);
  if (static_cast<int32_t>(now - stop) >= 0) {
    stats()[sl::w_done] = 1;
    sim_done();
  }
}

// ---- the board's clock ratio -----------------------------------------------------------
inline volatile uint16_t& tc(uint16_t offset) {
  return *reinterpret_cast<volatile uint16_t*>(0x1C0u + offset);
}
constexpr uint16_t tc_ctl = 0x00, tc_cctl0 = 0x02, tc_r = 0x10, tc_ccr0 = 0x12;
constexpr uint16_t steal_period = 128;  // Timer_B counts: 1 024 cycles, four simulator ticks
uint16_t steal_last = 0;                // Timer_B at the handler's last read
uint16_t steal_span = 0;                // its last run's own counts (interrupts within left out)
uint16_t steal_pre = 0;                 // the interrupts' counts within its last run
uint16_t steal_stub_at = 0;             // stub_counts at its last run
int32_t steal_debt = 0;                 // counts owed, in 1/64 count
// The firmware's time since the handler last ran owes 33/64 of itself (349/675 = 87.25 : 168.75,
// within 0.3 %); the handler's own time pays 64 a count. It burns with interrupts on: the
// firmware's interrupts preempt it at once (their latency is the board's), and their counts are
// the firmware's. No multiplication or 32-bit shift (no helper call: a short prologue).
// The handler's cycles outside its span (interrupt entry 6, the pushes and the first read before
// it; dint, the stores, the timer's next compare, the pops and reti 5 after it: main.cpp's
// isr_sim_clock_ratio, counted from its disassembly), in counts, rounded up (harsher).
constexpr uint16_t steal_overhead = 10;
inline uint16_t times33(uint16_t v) {
  uint16_t x = v;
  __asm__("rla %0\n rla %0\n rla %0\n rla %0\n rla %0" : "+r"(x));
  return static_cast<uint16_t>(x + v);
}
inline void steal() {
  const uint16_t entry = tbr();
  const uint16_t pre0 = isr_counts;
  enable_interrupts();  // the firmware's interrupts preempt all of it
  const uint16_t took = static_cast<uint16_t>(steal_span + steal_overhead);
  // The stand-ins' time (not the board's: the line's and the AD7739's work in their handlers)
  // is taken from the firmware's share like the loop's own.
  const uint16_t stub = static_cast<uint16_t>(stub_counts - steal_stub_at);
  steal_stub_at = stub_counts;
  uint16_t own = static_cast<uint16_t>(entry - steal_last + steal_pre);
  own = own > steal_overhead + stub ? static_cast<uint16_t>(own - steal_overhead - stub) : 0;
  if (own > 900) own = 900;  // (the image holds interrupts off for less)
  const uint16_t paid = static_cast<uint16_t>(took + stub);
  uint16_t pay = paid > 500 ? 500 : paid;
  __asm__("rla %0\n rla %0\n rla %0\n rla %0\n rla %0\n rla %0" : "+r"(pay));
  steal_debt += times33(own);
  steal_debt -= pay;
  stolen = static_cast<uint16_t>(stolen + took);
  volatile uint16_t* w = stats() + sl::w_stolen_lo;
  const uint16_t lo = static_cast<uint16_t>(w[0] + paid);
  w[0] = lo;
  if (lo < paid) w[1] = static_cast<uint16_t>(w[1] + 1);
  uint16_t burn = 0;
  if (steal_debt > 0) {
    uint16_t d = steal_debt > 32767 ? uint16_t{32767} : static_cast<uint16_t>(steal_debt);
    __asm__("rra %0\n rra %0\n rra %0\n rra %0\n rra %0\n rra %0" : "+r"(d));
    burn = d;
  }
  uint16_t now = entry, pre = 0;
  while (static_cast<uint16_t>(now - entry - pre) < burn) {
    now = tbr();
    pre = static_cast<uint16_t>(isr_counts - pre0);
  }
  disable_interrupts();
  now = tbr();
  pre = static_cast<uint16_t>(isr_counts - pre0);
  steal_pre = pre;
  const uint16_t span = static_cast<uint16_t>(now - entry);
  steal_span = span > pre ? static_cast<uint16_t>(span - pre) : 0;
  steal_last = now;
  tc(tc_ccr0) = static_cast<uint16_t>(tc(tc_r) + steal_period);
}

inline void steps_seen(uint16_t rebases) {
  stats()[sl::w_rebases] = rebases;
}

/// The top step rate the test asks the image to accept (sl::rate_limit_addr; 0: the board's).
inline uint16_t rate_limit_sps() {
  return *reinterpret_cast<const volatile uint16_t*>(sl::rate_limit_addr);
}

inline void init() {
  for (uint8_t w = 0; w < sl::w_count; ++w) stats()[w] = 0;
  script_at = 6;
  script_left = 0;
  line_on = false;
  tx_shifting = false;
  tx_n = 0;
  rx_fill_max = 0;
  rx_lost = 0;
  next_event();
  steal_last = tbr();
  steal_span = 0;
  steal_pre = 0;
  steal_debt = 0;
  tc(tc_ctl) = TBSSEL_2 | ID_3 | MC_2;
  tc(tc_ccr0) = static_cast<uint16_t>(tc(tc_r) + steal_period);
  tc(tc_cctl0) = CCIE;
}

}  // namespace sim
