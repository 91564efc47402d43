/// \file
/// \brief Where the MSP430F149 image built for mspdebug's simulator (GYROFLIP_F149_SIM,
/// sim_board.hpp) keeps what a test reads and writes: memory the simulator has and the F149 does
/// not (the simulator's 64 KB are all RAM), above the image's code and its .data's load image (the
/// test checks that the image ends below stats_addr: a reset copies .data from there again).
/// Every field is 16 bits (a
/// 32-bit value is two: low word first), little-endian, so the host reads it by offset.
/// Freestanding: tests/firmware/test_msp430_sim.cpp includes it.
#pragma once

#include <stdint.h>

namespace gyroflip::fw::simboard {

/// Figures the image measures (all 16-bit words; see `word`).
inline constexpr uint16_t stats_addr = 0xA800;
/// Bytes the device sent on its serial line, in order (line-coded wire bytes).
inline constexpr uint16_t tx_log_addr = 0xA900;
inline constexpr uint16_t tx_log_cap = 0x0F00;
/// Conversions: per conversion started, u32 start tick and u32 tick its result was read (0 when
/// never read).
inline constexpr uint16_t conv_log_addr = 0xB800;
inline constexpr uint16_t conv_log_cap = 256;
/// Stepper-port writes: u16 tick (low word), u8 port value, u8 lateness of the step interrupt
/// (ticks after its compare; 0xFF for a write that is not a step).
inline constexpr uint16_t port_log_addr = 0xC000;
static_assert(tx_log_addr + tx_log_cap <= conv_log_addr &&
              conv_log_addr + 8u * conv_log_cap <= port_log_addr);
inline constexpr uint16_t port_log_cap = 3328;
/// What the host sends: u16 count, u16 stop tick (low, high), then `count` events of u16 tick
/// (low, high), u16 length, `length` wire bytes, padded to an even length. The line delivers an
/// event's bytes one per byte time from its tick on; the image stops at the stop tick.
inline constexpr uint16_t script_addr = 0xF400;
inline constexpr uint16_t script_cap = 0x0BE0;

/// The stats words.
enum word : uint8_t {
  w_done = 0,  ///< 1 when the image reached the stop tick
  w_polls_lo,  ///< main-loop passes
  w_polls_hi,
  w_poll_max,        ///< the longest pass, in Timer_B counts (8 MCLK cycles)
  w_poll_max_at_lo,  ///< its tick
  w_poll_max_at_hi,
  w_isr_max,      ///< the longest step interrupt (its own time), Timer_B counts
  w_adc_isr_max,  ///< the longest conversion interrupt (its own time), Timer_B counts
  w_rx_lost,      ///< bytes the receive queue had no room for
  w_rx_max_fill,  ///< the receive queue's highest fill (bytes)
  w_wd_gap_lo,    ///< the longest gap between watchdog kicks after boot (ticks)
  w_wd_gap_hi,
  w_wd_last_lo,  ///< the last kick (ticks)
  w_wd_last_hi,
  w_port_writes,    ///< entries in the port log
  w_convs,          ///< entries in the conversion log
  w_tx_bytes,       ///< bytes in the transmit log
  w_step_late_max,  ///< the most ticks a step interrupt came after its compare
  w_polls_over_lo,  ///< passes longer than poll_limit Timer_B counts
  w_polls_over_hi,
  w_script_next,       ///< the next script event (events delivered)
  w_poll_max_from_lo,  ///< the tick the longest pass began
  w_poll_max_from_hi,
  /// From a conversion's end (/RDY) to the start of the dwell's next one, the firmware's own time
  /// (Timer_B counts): the longest, the sum and the number of such restarts.
  w_restart_max,
  w_restart_sum_lo,
  w_restart_sum_hi,
  w_restarts,
  /// Timer_B counts not the firmware's: the clock-ratio stand-in's and the other stand-ins'
  /// (sim_board.hpp): 349 of every 1 024 of the run.
  w_stolen_lo,
  w_stolen_hi,
  w_rebases,  ///< turns that ran dry and resumed with a new ramp (stepper::mover::rebase)
  w_count,
};
/// A word the test writes before each run: a top step rate the simulator image accepts instead
/// of the board's (limits.hpp), to measure the main loop above the board's limit
/// (Msp430Board.DISABLED_LongestPassAgainstTheTopRate); 0: the board's. In the 256 bytes the
/// test reads as the stats, above them.
inline constexpr uint16_t rate_limit_addr = 0xA8FE;
static_assert(stats_addr + 2u * w_count <= rate_limit_addr && rate_limit_addr + 2u <= tx_log_addr);
/// A pass longer than this (Timer_B counts: 1 ms at 5.5296 MHz) is counted in w_polls_over.
inline constexpr uint16_t poll_limit = 691;

/// The stand-in ADC's codes (deterministic, so a test knows every DWELL's sums): conversion
/// `index` of channel `ch` since boot.
[[nodiscard]] constexpr int32_t code_of(uint8_t ch, uint32_t index) {
  return ch == 0 ? 1000 + 37 * static_cast<int32_t>(index % 11) - 185
                 : -4000 + static_cast<int32_t>(index % 3);
}
/// The stand-in's revision register.
inline constexpr uint8_t revision = 0x29;

}  // namespace gyroflip::fw::simboard
