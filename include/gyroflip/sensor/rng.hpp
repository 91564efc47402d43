/// \file
/// \brief The simulator's uniform random numbers: xoshiro256** seeded through splitmix64, one
/// independent stream per error term (normal deviates: random.hpp).
#pragma once

#include <array>
#include <cstdint>

namespace gyroflip::sensor {

/// splitmix64 step (Steele, Lea & Flood 2014; Vigna's reference code): returns the next output
/// and advances `state`. Used only to expand seeds.
[[nodiscard]] inline std::uint64_t splitmix64(std::uint64_t& state) noexcept {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// Stream ids: one per random error term (never renumber: recordings depend on them).
enum class stream : std::uint64_t {
  angle_random_walk = 1,
  flicker = 2,
  rate_random_walk = 3,
  turn_on_bias = 4,
  adc_noise = 5,
  turn_on_g_sensitivity = 6,
  user = 16,  ///< first id free for callers (tests, Monte Carlo)
};

/// xoshiro256** 1.0 (Blackman & Vigna 2018): 256-bit state, period 2^256 - 1, ~1 ns/number.
class rng {
 public:
  /// The generator of stream `id` for run `seed`: state = four splitmix64 outputs of
  /// seed ^ (id * golden ratio constant) (never all zero).
  rng(std::uint64_t seed, stream id) noexcept {
    std::uint64_t sm = seed ^ (static_cast<std::uint64_t>(id) * 0xd1b54a32d192ed03ULL);
    for (auto& w : s_) w = splitmix64(sm);
  }

  /// Next 64 random bits.
  std::uint64_t next() noexcept {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Uniform in (0, 1): (top 53 bits + 1/2) 2^-53, never 0 (safe for log).
  double uniform_open() noexcept { return (static_cast<double>(next() >> 11) + 0.5) * 0x1.0p-53; }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) noexcept { return (x << k) | (x >> (64 - k)); }
  std::array<std::uint64_t, 4> s_{};
};

}  // namespace gyroflip::sensor
