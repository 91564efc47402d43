/// \file
/// \brief The data the sign-reversal method works on: recording rows, dwells and cycles.
///
/// A *row* is one line of a recording (one conversion, or an average of `n_avg`) at a position
/// of the table (an index into the recording's position_table, core/positions.hpp). A *dwell*
/// is a maximal run of rows at the same position (rows taken while the table turns are
/// skipped). A *cycle* is a dwell at the pair's +1 position and one at its -1 position
/// (method/flip_pair.hpp: 0 and 180 deg) reduced to the half-difference r (paper eqn 7) and the
/// half-sum c (the bias). FACTS §1.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string_view>

#include "gyroflip/core/positions.hpp"

namespace gyroflip::method {

inline constexpr double no_value = std::numeric_limits<double>::quiet_NaN();

/// One recording row. `position` is the index of its table position, table_moving (-1) while
/// the table turns; `temp_c` is NaN when the recording has no temperature.
struct row {
  double time_s = 0.0;
  int position = table_moving;
  double rate_dps = 0.0;
  double temp_c = no_value;
  std::uint32_t n_avg = 1;  ///< conversions averaged in this row (weight)
};

/// A dwell: the `n_avg`-weighted mean of consecutive rows at one position.
struct dwell {
  int position = 0;          ///< index of its table position
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

/// A demodulation scheme, by its row in the one table of schemes (method/demodulator.hpp,
/// `schemes()`; its names are the `--pairing` values). The two 0/180 schemes:
/// - `abba` (the default): each dwell against its two opposite-sign neighbours interpolated to
///   its time (the ABBA / three-point chop of metrology); cancels any linear bias drift exactly.
/// - `simple`: paper eqn 7, adjacent 0/180 dwells. A bias moving at b' leaks -b' dt/2 into r.
struct pairing {
  std::uint8_t id = 0;  ///< its row of schemes()
  static const pairing abba;
  static const pairing simple;
  static const pairing harmonic;
  constexpr bool operator==(const pairing&) const = default;
};
inline constexpr pairing pairing::abba{0};
inline constexpr pairing pairing::simple{1};
/// `harmonic`: N positions (3 or more), one estimate per visiting period by least squares
/// (method/harmonic.hpp); its calibration holds the bias and the harmonics as named terms.
inline constexpr pairing pairing::harmonic{2};

/// The scheme's name (schemes()[p.id].name); the scheme of a name, if the table has it.
[[nodiscard]] std::string_view to_string(pairing p) noexcept;
[[nodiscard]] std::optional<pairing> parse_pairing(std::string_view name) noexcept;

}  // namespace gyroflip::method
