/// \file
/// \brief The library's version and commit (version.hpp), from the build (CMakeLists.txt's
/// project version; cmake/build_commit.cmake).
#include "gyroflip/core/version.hpp"

#include "build_commit.inc"

namespace gyroflip {

std::string_view version() noexcept {
  return GYROFLIP_VERSION;
}

std::string_view build_commit() noexcept {
  return GYROFLIP_BUILD_COMMIT;
}

}  // namespace gyroflip
