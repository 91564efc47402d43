/// \file
/// \brief The one place where user-facing error messages are built (fmt's `report_error` idea).
///
/// Every message that names a position uses the compiler convention `FILE:LINE:COL: what`,
/// so editors can jump to it. Line and column are 1-based; 0 means "not applicable".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "gyroflip/core/result.hpp"

namespace gyroflip {

/// The largest magnitude of a number gyroflip takes from a user (a CSV cell, an option, a Python
/// argument, a sample): within it no sum or square the method and the analysis form overflows
/// (1e100 x 1e12 terms, squared, is 1e224), so every result is finite (docs/FORMATS.md).
inline constexpr double max_input_magnitude = 1e100;

/// Where in an input the problem is. `line`/`column` are 1-based, 0 when unknown.
struct source_location {
  std::string_view file;
  std::size_t line = 0;
  std::size_t column = 0;
};

/// `text` as it may appear inside a message: control characters and invalid UTF-8 as `\xNN`, the
/// direction controls as visible_controls() shows them, and at most `max_bytes` of it, followed by
/// `... (N more bytes)`. User text (a header field, a cell, a file name) goes through this, so
/// that no message echoes a 1 MiB line or raw control bytes to the terminal.
[[nodiscard]] std::string printable(std::string_view text, std::size_t max_bytes = 80);

/// `text` with Unicode's invisible direction and line controls shown as `\uNNNN`: the
/// bidirectional marks, embeddings, overrides and isolates (U+061C, U+200E, U+200F, U+202A..U+202E,
/// U+2066..U+2069), which reorder the text around them on a page or a terminal (the "Trojan
/// Source" attack, CVE-2021-42574), the line and paragraph separators U+2028/U+2029 (a second line
/// inside one), and U+FEFF. Everything else is kept as it is. printable() applies it.
[[nodiscard]] std::string visible_controls(std::string_view text);

/// True when `text` is valid UTF-8 (RFC 3629: no overlong forms, surrogates or code points
/// beyond U+10FFFF). JSON strings must be; a file name need not be.
[[nodiscard]] bool is_valid_utf8(std::string_view text) noexcept;

/// Error unless `file` is valid UTF-8: JSON output that names the file (`--json`, calibration
/// files) could not carry it. Says to rename the file.
[[nodiscard]] status check_name_for_json(std::string_view file);

/// `FILE:LINE:COL: what` (or `FILE:LINE: what`, or `FILE: what`) as a bad-input error.
[[nodiscard]] error input_error(const source_location& where, std::string_view what);

/// `FILE: what` as an I/O error (cannot open, is a directory, cannot write, ...).
[[nodiscard]] error io_error(std::string_view file, std::string_view what);

/// A runtime error without a position (the data are valid but cannot be processed).
[[nodiscard]] error runtime_error(std::string_view what);

/// A bad argument (not tied to a file): `what`.
[[nodiscard]] error usage_error(std::string_view what);

/// A bad or missing value of library parameter `parameter` (a field or argument name such as
/// `duration_s`): `what`, with `error::parameter` set so that a front end can name its option.
[[nodiscard]] error parameter_error(std::string_view parameter, std::string_view what);

/// `e` with `error::parameter` set (a file error that a parameter would resolve).
[[nodiscard]] error about_parameter(error e, std::string_view parameter);

}  // namespace gyroflip
