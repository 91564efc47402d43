/// \file
/// \brief The JSON convention (schema.hpp).
#include "gyroflip/io/schema.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "gyroflip/core/version.hpp"

namespace gyroflip::io {

std::string schema_name(std::string_view what, int n) {
  return fmt::format("gyroflip.{}/{}", what, n);
}

nlohmann::json schema_object(std::string_view what, int n) {
  return nlohmann::json{{"schema", schema_name(what, n)}, {"version", std::string(version())}};
}

}  // namespace gyroflip::io
