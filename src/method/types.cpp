/// \file
/// \brief Names of the pairings (see types.hpp).
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

std::string_view to_string(pairing p) noexcept {
  return p == pairing::simple ? "simple" : "abba";
}

std::optional<pairing> parse_pairing(std::string_view name) noexcept {
  if (name == "simple") return pairing::simple;
  if (name == "abba") return pairing::abba;
  return std::nullopt;
}

}  // namespace gyroflip::method
