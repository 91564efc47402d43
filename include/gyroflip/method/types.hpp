/// \file
/// \brief The data the sign-reversal method works on: recording rows, dwells and cycles.
///
/// A *row* is one line of a recording (one conversion, or an average of `n_avg`). A *dwell*
/// is a maximal run of rows at the same table angle (rows taken while the table turns are
/// skipped). A *cycle* is a 0 deg dwell and a 180 deg dwell reduced to the half-difference r
/// (paper eqn 7) and the half-sum c (the bias). FACTS §1.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>

namespace gyroflip::method {

inline constexpr double no_value = std::numeric_limits<double>::quiet_NaN();

/// One recording row. `angle_deg` is NaN while the table turns; `temp_c` is NaN when the
/// recording has no temperature.
struct row {
  double time_s = 0.0;
  double angle_deg = no_value;
  double rate_dps = 0.0;
  double temp_c = no_value;
  std::uint32_t n_avg = 1;  ///< conversions averaged in this row (weight)
};

/// A dwell: the `n_avg`-weighted mean of consecutive rows at one orientation.
struct dwell {
  int sign = 1;              ///< +1 at 0 deg, -1 at 180 deg
  double time_s = 0.0;       ///< weighted mean time of its rows
  double rate_dps = 0.0;     ///< weighted mean output y_0 or y_180
  double temp_c = no_value;  ///< weighted mean temperature (NaN if none)
  std::uint64_t weight = 0;  ///< total conversions (sum of n_avg)
};

/// One cycle of the method.
struct cycle {
  double time_s = 0.0;       ///< mean time of its two dwells
  double rate_dps = 0.0;     ///< r = (y_0 - y_180)/2 = w_in + w_E.s + d_g   (paper eqn 7)
  double bias_dps = 0.0;     ///< c = (y_0 + y_180)/2 = b                    (FACTS §1)
  double temp_c = no_value;  ///< mean temperature of its dwells (NaN if none)
};

/// How the two orientations are paired into a cycle value.
enum class pairing {
  /// Paper eqn 7: adjacent 0/180 dwells. A bias moving at b' leaks -b' dt/2 into r.
  simple,
  /// Each dwell against its two opposite-sign neighbours interpolated to its time (the
  /// ABBA / three-point chop of metrology); cancels any linear bias drift exactly.
  abba,
};

[[nodiscard]] std::string_view to_string(pairing p) noexcept;
[[nodiscard]] std::optional<pairing> parse_pairing(std::string_view name) noexcept;

}  // namespace gyroflip::method
