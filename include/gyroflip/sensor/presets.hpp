/// \file
/// \brief Sensor presets: the built-in `adxrs150` and `hz1-90-100a` (each figure tagged as a
/// datasheet value or an assumption) and user presets read from TOML files.
///
/// TOML format (docs/SIMULATOR.md): top-level `name = "..."`, optional `base = "adxrs150"` (start
/// from a built-in preset, default all zero), optional `description`, then any `sensor_params`
/// key (sensor/params.hpp) with a number. Unknown keys, non-numbers and out-of-range values are
/// errors reported as `FILE:LINE:COL: what`.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/sensor/params.hpp"

namespace gyroflip::sensor {

struct preset {
  std::string name;
  std::string description;
  sensor_params params;
  /// key -> where the value comes from ("datasheet ...", "assumption: ...", "file:line").
  std::vector<std::pair<std::string, std::string>> sources;

  /// The source text of `key` ("" when not recorded).
  [[nodiscard]] std::string_view source_of(std::string_view key) const;
};

/// Whether `p`'s value of `key` is one a built-in preset fitted to the paper's measurements
/// (presets.cpp's "paper" tag: a source "paper Tab. 3 ...", "paper Tab. 4 ...", "paper Figs.
/// ..." or "fitted to paper ..."; a datasheet value or an assumption is not): in a TOML preset,
/// a value its base gave that the file did not restate (a restated key's source is the file's
/// line). Fifth review of issue 31, F10: such a value predicts nothing about the data it was
/// fitted to.
[[nodiscard]] bool fitted_to_paper(const preset& p, std::string_view key);

/// The built-in presets, in a fixed order.
[[nodiscard]] const std::vector<preset>& builtin_presets();

/// The built-in preset `name` (case-sensitive), or nullptr.
[[nodiscard]] const preset* find_builtin(std::string_view name);

/// Parses a TOML preset from `text`; `file` names it in messages.
[[nodiscard]] result<preset> parse_toml_preset(std::string_view text, std::string_view file);

/// A built-in name, or else a path to a TOML preset file.
[[nodiscard]] result<preset> load_preset(std::string_view name_or_file);

}  // namespace gyroflip::sensor
