/// \file
/// \brief The library's version (the project's, as the command and the Python module report it).
#pragma once

#include <string_view>

namespace gyroflip {

/// gyroflip's version, e.g. "0.1.0".
[[nodiscard]] std::string_view version() noexcept;

}  // namespace gyroflip
