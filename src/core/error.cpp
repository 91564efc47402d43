/// \file
/// \brief Builds the user-facing error messages (see error.hpp).
#include "gyroflip/core/error.hpp"

#include <fmt/format.h>

namespace gyroflip {

error input_error(const source_location& where, std::string_view what) {
  if (where.line != 0 && where.column != 0)
    return {errc::bad_input,
            fmt::format("{}:{}:{}: {}", where.file, where.line, where.column, what)};
  if (where.line != 0)
    return {errc::bad_input, fmt::format("{}:{}: {}", where.file, where.line, what)};
  return {errc::bad_input, fmt::format("{}: {}", where.file, what)};
}

error io_error(std::string_view file, std::string_view what) {
  return {errc::io, fmt::format("{}: {}", file, what)};
}

error runtime_error(std::string_view what) {
  return {errc::runtime, std::string(what)};
}

error usage_error(std::string_view what) {
  return {errc::bad_input, std::string(what)};
}

}  // namespace gyroflip
