/// \file
/// \brief One series' noise terms as the JSON object `gyroflip noise --json` prints and
/// `gyroflip.noise()` returns (keys in docs/ANALYSIS.md, "noise --json"): each term in the
/// field's units with its interval, or null with its upper limit when the data do not resolve
/// it; the OADEV points, the misfit points and the slope read-offs. Includes only nlohmann's
/// forward header.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "gyroflip/analysis/noise.hpp"

namespace gyroflip::io {

/// What was analysed and what came out.
struct noise_report {
  std::string file;             ///< the input's name
  std::string column;           ///< its column
  std::string input = "rate";   ///< "rate" or "angle"
  std::string units = "deg/s";  ///< the samples' unit
  double deg_per_unit = 1.0;    ///< degrees per unit of the samples (rad/s: 180/pi)
  double tau0_s = 0.0;
  std::size_t samples = 0;
  analysis::noise_series series;
  analysis::noise_analysis result;
};

/// The JSON object of `r`, schema gyroflip.noise/1 (io/schema.hpp; numbers unchecked: pass it
/// through finite_dump).
[[nodiscard]] nlohmann::json noise_json(const noise_report& r);

}  // namespace gyroflip::io
