/// \file
/// \brief Faults on the emulated link, device to host: bit flips at a bit error rate and dropped
/// bytes, seeded, with the count of frames they touched (the truth a recorder's counts of corrupt
/// and missing frames are checked against).
#pragma once

#include <cstdint>
#include <random>

namespace gyroflip::host {

struct link_fault_counts {
  std::uint64_t bytes = 0;          ///< bytes offered
  std::uint64_t bits_flipped = 0;   ///< bits inverted
  std::uint64_t bytes_dropped = 0;  ///< bytes never delivered
  std::uint64_t frames = 0;         ///< frames offered (delimiter runs of the clean stream)
  std::uint64_t frames_hit = 0;     ///< frames with a flipped or dropped byte, delimiter included
};

class link_faults {
 public:
  /// Each bit flips with probability `ber`, each byte is dropped with probability `drop`
  /// (both in [0, 1)), independently; `seed` fixes the pattern.
  link_faults(double ber, double drop, std::uint64_t seed);
  /// One byte of the clean stream: false when it is dropped, else the byte to deliver in `out`.
  bool pass(std::uint8_t in, std::uint8_t& out);
  /// True when a fault touched the frame whose delimiter run the last byte completed (a frame
  /// may still arrive whole: the line code corrects one bit per wire byte).
  [[nodiscard]] bool last_frame_hit() const noexcept { return last_hit_; }
  [[nodiscard]] const link_fault_counts& counts() const noexcept { return counts_; }

 private:
  std::mt19937_64 rng_;
  bool flips_, drops_;
  std::geometric_distribution<std::uint64_t> flip_gap_, drop_gap_;
  // Events are spaced by geometric gaps (the failures before the next event): one draw per
  // fault, not one per bit. Positions to the next event, counted down.
  std::uint64_t bits_to_flip_ = 0, bytes_to_drop_ = 0;
  bool hit_ = false, last_hit_ = false;
  unsigned zeros_ = 0;  // zero wire bytes in a row (a frame's end)
  link_fault_counts counts_;
};

}  // namespace gyroflip::host
