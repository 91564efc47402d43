/// \file
/// \brief The one gate every number gyroflip writes passes through: text holding a `nan` or `inf`
/// number, or JSON holding a non-finite number (which nlohmann would write as null), is refused
/// instead of written, so a run either writes only finite numbers or fails (exit 2) with nothing
/// written. The arithmetic stays finite for every accepted input (input ranges in
/// docs/FORMATS.md); this gate makes that a guarantee of every output. Used by every writer of
/// the CLI, by io::to_json (calibration files) and by the Python module. Includes only nlohmann's
/// forward header.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "gyroflip/core/result.hpp"
#include "gyroflip/method/compensation.hpp"

namespace gyroflip::io {

/// Error unless every number in `text` (CSV rows, a printed summary) is finite: a token `nan`,
/// `inf` or `infinity` (any case, any sign) between separators fails. `what` names the output.
[[nodiscard]] status check_finite(std::string_view text, std::string_view what);

/// Error unless every value is finite: the same gate for numbers handed over as numbers (the
/// Python module's arrays, before they are returned).
[[nodiscard]] status check_finite(std::span<const double> values, std::string_view what);

/// Error unless every number of compensated cycles (time, rate, bias, dN; a temperature may be
/// absent, NaN) and of their summary is finite: what `compensate` writes and Python's
/// `compensate` returns.
[[nodiscard]] status check_finite(std::span<const method::compensated_cycle> cycles,
                                  const method::compensation_summary& summary,
                                  std::string_view what);

/// The JSON text of `j`, or an error if any number in it is not finite. Invalid UTF-8 in strings
/// is replaced (U+FFFD), never thrown.
[[nodiscard]] result<std::string> finite_dump(const nlohmann::json& j, std::string_view what);

}  // namespace gyroflip::io
