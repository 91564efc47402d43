/// \file
/// \brief The library's version (version.hpp), from the build (CMakeLists.txt's project version).
#include "gyroflip/core/version.hpp"

namespace gyroflip {

std::string_view version() noexcept {
  return GYROFLIP_VERSION;
}

}  // namespace gyroflip
