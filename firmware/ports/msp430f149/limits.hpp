/// \file
/// \brief What the MSP430F149 board can produce: the one source of its limits, used by its image
/// (board_facts, main.cpp) and by the host's recorder to name the limit when the board refuses a
/// CONFIGURE (docs/FIRMWARE.md, "Rates the board can produce"). Freestanding (<stdint.h> only).
#pragma once

#include <stdint.h>

namespace gyroflip::fw::msp430f149 {

/// The highest top step rate (steps/s) the image accepts in CONFIGURE (above: NAK bad_arg): the
/// highest at which the main loop's longest pass stays below the 96-byte receive queue's 8.33 ms
/// with margin when the host sends behind command bursts at the ramps' tops. Measured
/// (Msp430Board.DISABLED_LongestPassAgainstTheTopRate; docs/PERFORMANCE.md, "Fifth pass"):
/// 5.89 / 6.20 / 7.02 / 7.80 / 8.28 / 8.23 / 9.29 / 9.62 ms at 800 / 1 000 / 1 200 / 1 400 /
/// 1 500 / 1 600 / 1 800 / 2 000 steps/s, nothing lost to 1 500, 4-11 bytes lost from 1 600.
/// 1 200 keeps 16 % margin (7.02 ms); 1 400-1 500 meet the bound without margin, and a rate at
/// which the board can lose a command's bytes must not be one it accepts (the paper's rig and
/// the simulator's default run at 400). With the HAL's block reads and writes ("Seventh pass"):
/// 5.31 / 6.20 / 6.75 / 6.42 / 6.53 / 7.23 / 8.25 / 7.72 ms at the same rates, nothing lost to
/// 1 600, 3 and ~33 bytes lost at 1 800 and 2 000: 1 500 would now keep 22 % margin (not raised
/// yet); 2 000 needs a cheaper ramp interval. Msp430Board.BurstsWithTheHostSendingBehindThemLose
/// Nothing runs at this limit.
inline constexpr uint16_t max_step_rate_sps = 1200;

}  // namespace gyroflip::fw::msp430f149
