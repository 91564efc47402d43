/// \file
/// \brief How many digits a number with an uncertainty supports: the one rule of every "v ± u"
/// the report, the budget and the figures print.
#pragma once

#include <algorithm>
#include <cmath>

namespace gyroflip {

/// The decimals that show an uncertainty `u` > 0 to two significant digits (1.2e-5 -> 6; 0.35
/// -> 2; 120 -> 0), at most 15. The value beside it takes the same decimals.
[[nodiscard]] inline int decimals_of_error(double u) {
  return std::clamp(1 - static_cast<int>(std::floor(std::log10(u))), 0, 15);
}

}  // namespace gyroflip
