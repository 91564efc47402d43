/// \file
/// \brief What the MSP430F149 board can produce: the one source of its limits, used by its image
/// (board_facts, main.cpp) and by the host's recorder to name the limit when the board refuses a
/// CONFIGURE (docs/FIRMWARE.md, "Rates the board can produce"). Freestanding (<stdint.h> only).
#pragma once

#include <stdint.h>

namespace gyroflip::fw::msp430f149 {

/// The highest top step rate (steps/s) the image accepts in CONFIGURE (above: NAK bad_arg). At
/// 2 000 steps/s every step interval keeps the ramp to a tick with commands at the ramps' tops
/// (Msp430Board.CommandsAtTheTopOfTheRampDoNotStarveTheSteps). A lower limit would not bound
/// the main loop's longest pass when the host sends behind a burst: that pass is 11-14 ms at
/// every top rate from 800 to 2 000 steps/s (docs/PERFORMANCE.md, "The F149's top step rate").
inline constexpr uint16_t max_step_rate_sps = 2000;

}  // namespace gyroflip::fw::msp430f149
