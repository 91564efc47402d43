/// \file
/// \brief Faults on the emulated link (link_faults.hpp).
#include "host/emulator/link_faults.hpp"

namespace gyroflip::host {

link_faults::link_faults(double ber, double drop, std::uint64_t seed)
    : rng_(seed),
      flips_(ber > 0.0),
      drops_(drop > 0.0),
      flip_gap_(flips_ ? ber : 0.5),
      drop_gap_(drops_ ? drop : 0.5) {
  if (flips_) bits_to_flip_ = flip_gap_(rng_);
  if (drops_) bytes_to_drop_ = drop_gap_(rng_);
}

bool link_faults::pass(std::uint8_t in, std::uint8_t& out) {
  ++counts_.bytes;
  out = in;
  bool delivered = true;
  if (drops_) {
    if (bytes_to_drop_ == 0) {
      delivered = false;
      hit_ = true;
      ++counts_.bytes_dropped;
      bytes_to_drop_ = drop_gap_(rng_);
    } else {
      --bytes_to_drop_;
    }
  }
  if (flips_) {
    // The byte's 8 bits, whether or not it is delivered (the line carried them).
    for (int bit = 0; bit < 8; ++bit) {
      if (bits_to_flip_ == 0) {
        out = static_cast<std::uint8_t>(out ^ (1u << bit));
        if (delivered) {
          hit_ = true;
          ++counts_.bits_flipped;
        }
        bits_to_flip_ = flip_gap_(rng_);
      } else {
        --bits_to_flip_;
      }
    }
  }
  // A frame ends with a run of zero wire bytes (protocol v2's line code: 4 zeros; inside a frame
  // there are never more than 2 in a row): the 4th zero closes it.
  zeros_ = in == 0x00 ? zeros_ + 1 : 0;
  if (zeros_ == 4) {
    ++counts_.frames;
    if (hit_) ++counts_.frames_hit;
    last_hit_ = hit_;
    hit_ = false;
  }
  return delivered;
}

}  // namespace gyroflip::host
