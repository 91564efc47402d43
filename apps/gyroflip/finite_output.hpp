/// \file
/// \brief Printing on stdout through the finite-output gate (gyroflip/io/finite_output.hpp).
#pragma once

#include <string_view>

#include <nlohmann/json_fwd.hpp>

#include "gyroflip/core/result.hpp"
#include "gyroflip/io/finite_output.hpp"

namespace gyroflip::app {

using io::check_finite;
using io::finite_dump;

/// `j` (an object) with the JSON convention's `schema` gyroflip.WHAT/N and `version`
/// (io/schema.hpp) added: what every subcommand prints with --json.
[[nodiscard]] nlohmann::json with_schema(std::string_view what, int n, nlohmann::json j);

/// Prints `j` as one line of JSON on stdout when every number in it is finite.
[[nodiscard]] status print_json(const nlohmann::json& j);

/// Prints `text` on stdout when `check_finite` passes; else prints nothing and returns the error.
[[nodiscard]] status print_checked(std::string_view text, std::string_view what);

}  // namespace gyroflip::app
