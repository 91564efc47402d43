/// \file
/// \brief Maps library errors to the documented exit codes.
#include <cstdio>

#include "commands.hpp"

namespace gyroflip::app {

int report(const error& e) {
  std::fprintf(stderr, "gyroflip: error: %s\n", e.message.c_str());
  return e.code == errc::runtime ? 1 : 2;
}

}  // namespace gyroflip::app
