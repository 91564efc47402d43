/// \file
/// \brief Is a series modulated by the flip? An uncompensated flip recording's `rate_dps` switches
/// with `angle_deg` (by 2 dN = 2 (d_g + w_E.s), paper eqn 7, plus the input), so its Allan curve
/// shows the flipping - a square wave - not the sensor: a "resolved" K = 717 deg/h/sqrt(h) and
/// Q = 0.16 deg on one (issue 13 item 12). `gyroflip adev`/`noise` refuse such a series.
#pragma once

#include <cstddef>
#include <span>

namespace gyroflip::method {

struct flip_modulation {
  bool modulated = false;
  double mean_0 = 0.0;    ///< mean of the values at 0 deg
  double mean_180 = 0.0;  ///< mean of the values at 180 deg
  std::size_t n_0 = 0, n_180 = 0;
};

/// Compares the values at 0 deg with those at 180 deg (`angle_deg` NaN: turning, ignored).
/// Modulated when both positions have >= 2 values, the two means differ by more than 10 standard
/// errors (sqrt(v0/n0 + v180/n180)), and the square wave of half that difference carries more
/// than 1 % of the within-position variance (below that it hardly moves any Allan point).
[[nodiscard]] flip_modulation detect_flip_modulation(std::span<const double> values,
                                                     std::span<const double> angle_deg);

}  // namespace gyroflip::method
