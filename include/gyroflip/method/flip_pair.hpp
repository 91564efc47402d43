/// \file
/// \brief The two positions the 0/180 demodulators (pairings `simple` and `abba`) use, and the
/// sign each stands for: the one rule that turns a table's positions into the method's +-1.
///
/// Rule (docs/METHOD-NOTES.md): `plus` (+1) is the table's position nearest 0 deg on the circle
/// (359.9 is 0.1 deg from 0; of two equally near, the smaller angle: 90 before 270), `minus`
/// (-1) the position 180 deg from it. For the paper's table 0/180 that is +1 at 0 deg and -1 at
/// 180 deg, as the method has always taken them, so the pairings' numbers are unchanged. Dwells at
/// any other position of the table are not the pair's: the 0/180 demodulators pass over their
/// rows as over rows taken while the table turns.
#pragma once

#include <string>

#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/result.hpp"

namespace gyroflip::method {

struct flip_pair {
  int plus = 0;   ///< index of the +1 position (nearest 0 deg)
  int minus = 1;  ///< index of the -1 position (180 deg from `plus`)
  /// Whether a row or dwell at `position` belongs to the pair.
  [[nodiscard]] constexpr bool holds(int position) const noexcept {
    return position == plus || position == minus;
  }
  /// The sign of a position of the pair: +1 at `plus`, -1 at `minus`.
  [[nodiscard]] constexpr int sign(int position) const noexcept {
    return position == plus ? 1 : -1;
  }
  bool operator==(const flip_pair&) const = default;
};

/// How far from 180 deg two positions may be and still be the pair (deg): half the device's
/// resolution of a table angle (a hundredth of a degree, docs/PROTOCOL.md).
inline constexpr double pair_tolerance_deg = 0.005;

/// The pair of `table` by the rule above. Error (naming `source`) when the table holds no
/// position 180 deg from the one nearest 0 deg.
[[nodiscard]] result<flip_pair> flip_pair_of(const position_table& table,
                                             const std::string& source);

}  // namespace gyroflip::method
