/// \file
/// \brief Calibration of dN from a stationary recording (paper eqns 8-11) and its split into
/// the Earth-rate and g-sensitivity terms.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "gyroflip/core/result.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// Fewest cycles for which a calibration (mean and spread) is computed.
inline constexpr std::size_t min_cycles = 3;

/// A standard error of the mean that accounts for correlated noise.
struct correlated_error {
  double stderr_dps = 0.0;
  std::size_t m = 0;  ///< averaging factor (cycles) of the Allan variance used; 0 = naive
  bool resolved =
      false;  ///< false when the series was too short (< 16) and the naive error is returned
};

/// Standard error of the mean of a correlated series y_1..y_n (docs/METHOD-NOTES.md):
/// se^2 = max(s^2/n, AVAR(m*) m*/n) with m* = floor(n/8) and AVAR the overlapping Allan
/// variance of y (NIST SP1065 eqn 11, on the integrated series). For white noise
/// AVAR(m) = s^2/m, so this equals the naive error; flicker or random walk at averaging
/// times up to m* make it larger. Noise that only shows beyond n/8 cycles cannot be seen.
[[nodiscard]] correlated_error correlated_stderr(std::span<const double> y, double naive_stderr);

/// Result of calibrating one stationary recording.
struct calibration {
  double delta_n_dps = 0.0;            ///< dN = mean of r over cycles (eqns 8-11)
  double std_dps = 0.0;                ///< sample std of the cycle values
  double stderr_dps = 0.0;             ///< naive standard error std/sqrt(n)
  double stderr_correlated_dps = 0.0;  ///< see correlated_stderr()
  std::size_t correlated_m = 0;        ///< averaging factor behind stderr_correlated_dps
  std::size_t cycles = 0;
  double temp_c = no_value;    ///< mean cycle temperature (NaN without temperatures)
  double duration_s = 0.0;     ///< time between the first and last cycle
  double bias_mean_dps = 0.0;  ///< mean of the half-sums c (the sensor's bias)
};

/// One named term of dN (issue 33): a constant a scheme's calibration estimates and compensation
/// subtracts. The 0/180 schemes estimate one, `delta_n` (dN = W_E.s + d_g, paper eqns 8-11: the
/// calibration's delta_n_dps); a scheme of more positions names more (demodulator.hpp, its row of
/// schemes()).
struct delta_n_term {
  std::string name;
  double value_dps = 0.0;
  double stderr_correlated_dps = 0.0;  ///< see correlated_stderr()
  bool operator==(const delta_n_term&) const = default;
};

/// The name of the 0/180 schemes' one term.
inline constexpr std::string_view delta_n_term_name = "delta_n";

/// dN and its uncertainty from the cycles of a stationary recording (w_in = 0).
/// Error (runtime) if there are fewer than `min_cycles` cycles.
[[nodiscard]] result<calibration> calibrate(std::span<const cycle> cycles);

/// dN = d_g + W_E.s (eqn 11) split with a known geometry.
struct delta_n_split {
  double earth_rate_dps = 0.0;  ///< W_E . s at the latitude (eqn 9 for a north axis)
  double g_term_dps = 0.0;      ///< d_g = dN - W_E . s (eqn 10)
};

/// Splits dN into the Earth term and the g-sensitivity term (eqns 9-11, FACTS §2).
[[nodiscard]] delta_n_split split_delta_n(double delta_n_dps, double lat_deg,
                                          const earth::ned_vector& axis);

}  // namespace gyroflip::method
