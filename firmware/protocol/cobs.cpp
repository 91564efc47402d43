/// \file
/// \brief COBS (see cobs.hpp).
#include "cobs.hpp"

namespace gyroflip::protocol {

size_t cobs_encode(const uint8_t* src, size_t n, uint8_t* dst, size_t cap) {
  if (cap < cobs_max_encoded(n)) return 0;
  size_t code_at = 0;  // where the current block's code byte goes
  size_t out = 1;
  uint8_t code = 1;
  for (size_t i = 0; i < n; ++i) {
    if (src[i] == 0) {
      dst[code_at] = code;
      code_at = out++;
      code = 1;
      continue;
    }
    dst[out++] = src[i];
    if (++code == 0xFF) {  // a full block of 254 data bytes: a new block starts
      dst[code_at] = code;
      code_at = out++;
      code = 1;
    }
  }
  dst[code_at] = code;
  return out;
}

long cobs_decode(const uint8_t* src, size_t n, uint8_t* dst, size_t cap) {
  size_t in = 0;
  size_t out = 0;
  while (in < n) {
    const uint8_t code = src[in++];
    if (code == 0) return -1;
    const size_t run = static_cast<size_t>(code) - 1u;
    if (run > n - in) return -1;  // the block claims bytes past the end
    if (out + run > cap) return -1;
    for (size_t k = 0; k < run; ++k) {
      if (src[in] == 0) return -1;
      dst[out++] = src[in++];
    }
    // A block shorter than 254 data bytes stood for a 0x00, except the last one.
    if (code != 0xFF && in < n) {
      if (out >= cap) return -1;
      dst[out++] = 0;
    }
  }
  return static_cast<long>(out);
}

}  // namespace gyroflip::protocol
