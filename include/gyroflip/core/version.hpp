/// \file
/// \brief The library's version (the project's, as the command and the Python module report it)
/// and the git commit it was built from (a report's provenance).
#pragma once

#include <string_view>

namespace gyroflip {

/// gyroflip's version, e.g. "0.1.0".
[[nodiscard]] std::string_view version() noexcept;

/// The git commit the library was built from (40 hex digits, `+modified` when the source tree
/// differed from it), or "unknown" when it was not built from a git checkout.
[[nodiscard]] std::string_view build_commit() noexcept;

}  // namespace gyroflip
