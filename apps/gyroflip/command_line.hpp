/// \file
/// \brief What several subcommands read alike: the geometry of `--latitude` and `--axis`, and the
/// command line as run (a report's provenance).
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/io/calibration_file.hpp"

namespace gyroflip::app {

/// `--latitude DEG --axis AXIS` (both or neither; `lat_deg` NaN and `axis` empty: not given).
/// Errors: one without the other, a latitude outside [-90, 90], an axis that is no direction.
[[nodiscard]] result<std::optional<io::calibration_geometry>> geometry_option(
    double lat_deg, const std::string& axis);

/// The command line as the shell ran it: the words joined by spaces, each that a shell would
/// split or expand quoted ('...'), so that it can be pasted back.
[[nodiscard]] std::string shell_command(const std::vector<std::string>& words);

}  // namespace gyroflip::app
