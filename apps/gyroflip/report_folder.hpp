/// \file
/// \brief A report folder (`report -o DIR`, `reproduce -o DIR`) is built in a staging folder
/// beside DIR and renamed onto it at the end, so that DIR is never half written: DIR must be new,
/// an empty folder or an earlier report (it has index.html and summary.json), which it replaces.
#pragma once

#include <string>

#include "gyroflip/core/result.hpp"

namespace gyroflip::app {

/// Creates the staging folder (with figures/ inside) for `out`. Errors: `out` is something else.
[[nodiscard]] result<std::string> staging_folder(const std::string& out);
/// Renames `staging` onto `out` (an earlier report there is removed after).
[[nodiscard]] status publish(const std::string& staging, const std::string& out);

}  // namespace gyroflip::app
