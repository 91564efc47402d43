/// \file
/// \brief The 0/180 demodulators' pair of positions (see flip_pair.hpp).
#include "gyroflip/method/flip_pair.hpp"

#include <cmath>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::method {

result<flip_pair> flip_pair_of(const position_table& table, const std::string& source) {
  const auto ps = table.positions();
  if (ps.empty()) return input_error({source}, "no table positions");
  // The position nearest 0 deg; of two equally near, the smaller angle.
  const table_position* plus = &ps.front();
  for (const auto& p : ps) {
    const double off = angle_between_deg(p.angle_deg, 0.0);
    const double best = angle_between_deg(plus->angle_deg, 0.0);
    if (off < best || (off == best && p.angle_deg < plus->angle_deg)) plus = &p;
  }
  for (const auto& p : ps)
    if (angle_between_deg(p.angle_deg, plus->angle_deg) >= 180.0 - pair_tolerance_deg)
      return flip_pair{plus->index, p.index};
  if (ps.size() == 1)
    return input_error(
        {source},
        fmt::format("the table never turns (every row is at {} deg): the method needs "
                    "dwells at both {} and {} deg (an unflipped recording is for adev "
                    "and noise, not for calibrate or compensate)",
                    plus->angle_deg, plus->angle_deg, std::fmod(plus->angle_deg + 180.0, 360.0)));
  return input_error({source},
                     fmt::format("the table's positions ({} deg) hold none 180 deg from {} deg, "
                                 "the one nearest 0: the pairings simple and abba need that pair",
                                 table.describe(), plus->angle_deg));
}

}  // namespace gyroflip::method
