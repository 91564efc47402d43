/// \file
/// \brief The one convention of every JSON object gyroflip prints or writes (`--json` of every
/// command, calibration files, a report's and a reproduction's summary.json, what Python returns
/// as the same objects): it carries `"schema": "gyroflip.<what>/<N>"` and `"version"`, gyroflip's
/// version. N goes up when a key changes meaning or goes; new keys do not change it
/// (docs/cli.md, "JSON objects"). Includes only nlohmann's forward header.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

namespace gyroflip::io {

/// "gyroflip.<what>/<n>".
[[nodiscard]] std::string schema_name(std::string_view what, int n);

/// A JSON object holding `schema` (schema_name) and `version` (gyroflip::version()), to which
/// the caller adds its keys.
[[nodiscard]] nlohmann::json schema_object(std::string_view what, int n);

}  // namespace gyroflip::io
