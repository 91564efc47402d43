/// \file
/// \brief The IEEE 952 terms read off an Allan deviation curve by hand, as the field does
/// (IEEE Std 952-1997 Annex C; El-Sheimy, Hou & Niu 2008): the value of the -1/2 slope line at
/// tau = 1 s (N), of the +1/2 slope line at tau = 3 s (K), and the floor over 0.664 (B). They sit
/// next to the fit (noise_fit.hpp) so that a reader can compare with a datasheet or a paper.
#pragma once

#include <optional>
#include <span>

#include "gyroflip/analysis/allan.hpp"

namespace gyroflip::analysis {

struct slope_readoffs {
  /// N: sigma(1 s) of the white-noise line sigma = N / sqrt(tau) through the point of the curve
  /// whose log-log slope is nearest -1/2 (deg/s/sqrt(Hz) when the curve is in deg/s).
  std::optional<double> arw;
  double arw_from_tau_s = 0.0;  ///< the point the line went through
  /// K: sigma(3 s) of the line sigma = K sqrt(tau / 3) through the point whose slope is nearest
  /// +1/2; empty when the curve never rises.
  std::optional<double> rrw;
  double rrw_from_tau_s = 0.0;
  /// B = floor / 0.6643 (flicker floor sqrt(2 ln 2 / pi) B): the curve's first local minimum
  /// (a later one at long tau rests on a few clusters), or its last point when it still falls.
  double bias_instability = 0.0;
  double floor_tau_s = 0.0;
  double floor_dev = 0.0;
  /// True when the floor point has a higher point after it (a real minimum), false when the
  /// curve still falls at its longest tau (B is then an upper bound).
  bool floor_is_minimum = false;
};

/// Read-offs from OADEV points in increasing tau (at least 2). Slopes are those of the segments
/// between neighbouring points; a segment's line goes through its two points' geometric mean.
[[nodiscard]] slope_readoffs read_off_terms(std::span<const deviation_point> pts);

}  // namespace gyroflip::analysis
