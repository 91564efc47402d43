/// \file
/// \brief Names of the pairings: the table of schemes (types.hpp, demodulator.hpp).
#include "gyroflip/method/types.hpp"

#include "gyroflip/method/demodulator.hpp"

namespace gyroflip::method {

std::string_view to_string(pairing p) noexcept {
  return scheme_of(p).name;
}

std::optional<pairing> parse_pairing(std::string_view name) noexcept {
  const auto all = schemes();
  for (std::size_t i = 0; i < all.size(); ++i)
    if (all[i].name == name) return pairing{static_cast<std::uint8_t>(i)};
  return std::nullopt;
}

}  // namespace gyroflip::method
