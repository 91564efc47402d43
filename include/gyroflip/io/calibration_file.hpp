/// \file
/// \brief The calibration file (`gyroflip calibrate -o CAL.json`, read by `compensate
/// --calibration`): the same JSON object that `calibrate --json` prints (docs/FORMATS.md).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/delta_n_model.hpp"

namespace gyroflip::io {

/// Geometry given to `calibrate` (both or neither).
struct calibration_geometry {
  double lat_deg = 0.0;
  earth::ned_vector axis;
};

/// One input file's calibration.
struct calibration_entry {
  std::string file;
  method::calibration cal;
};

/// Everything a calibration run produced.
struct calibration_record {
  method::pairing pairing = method::pairing::abba;
  method::calibration pooled;  ///< all cycles of all files together
  std::optional<calibration_geometry> geometry;
  std::vector<calibration_entry> files;
  std::optional<method::delta_n_model> model;  ///< dN(T), when several files were given
};

/// JSON text of a calibration (one line, keys as in docs/FORMATS.md).
[[nodiscard]] result<std::string> to_json(const calibration_record& rec,
                                          std::string_view tool_version);

/// Reads a calibration file. Errors name the file (and the key that is wrong).
[[nodiscard]] result<calibration_record> read_calibration_file(const std::string& path);

}  // namespace gyroflip::io
