/// \file
/// \brief The simulator's normal deviates: a ziggurat generator of our own on the uniform streams
/// of rng.hpp (xoshiro256**, one independent stream per error term).
///
/// `std::normal_distribution` is implementation-defined (libstdc++ and libc++ give different
/// numbers), so it is never used: the same seed gives the same recording on any machine.
/// Streams are derived from (seed, stream id), so turning one error term off leaves the random
/// numbers of all other terms unchanged.
#pragma once

#include <cstddef>
#include <cstdint>

#include "gyroflip/sensor/detail/ziggurat.hpp"
#include "gyroflip/sensor/rng.hpp"

namespace gyroflip::sensor {

/// A standard normal N(0, 1) deviate. Fast path (98.8 %): one 64-bit number, one multiply,
/// one compare; low 8 bits pick the layer, the top 53 bits the signed uniform (disjoint bits,
/// so no layer/value correlation, Doornik 2005 section 4).
[[nodiscard]] inline double normal(rng& g, const detail::ziggurat_tables& z) noexcept {
  const std::uint64_t r = g.next();
  const auto i = static_cast<std::size_t>(r & 0xffU);
  const std::int64_t s53 = static_cast<std::int64_t>(r) >> 11;  // in [-2^52, 2^52)
  if (static_cast<std::uint64_t>(s53) + z.shift[i] <= z.span[i]) [[likely]] {
    return static_cast<double>(s53) * z.x_scaled[i];
  }
  const double u = static_cast<double>(s53) * 0x1.0p-52;
  const detail::slow_normal s = detail::normal_slow(g, z, i, u);
  g = s.state;
  return s.value;
}

/// A normal stream: an `rng` plus the shared ziggurat tables (a value type, cheap to copy).
class normal_stream {
 public:
  normal_stream(std::uint64_t seed, stream id) : g_(seed, id), z_(&detail::ziggurat()) {}
  /// N(0, 1).
  double next() noexcept { return normal(g_, *z_); }
  /// Fills `out[0..n)` with N(0, 1) (the same numbers as n calls of next(), but faster: a
  /// tight loop keeps the generator state in registers).
  void fill(double* out, std::size_t n) noexcept {
    rng g = g_;
    const detail::ziggurat_tables& z = *z_;
    for (std::size_t k = 0; k < n; ++k) out[k] = normal(g, z);
    g_ = g;
  }
  rng& uniform() noexcept { return g_; }

  /// Fills a[0..n) from stream `sa` and b[0..n) from `sb` in one loop: the same numbers as
  /// sa.fill(a, n) and sb.fill(b, n), but the two generators' dependency chains interleave
  /// (the simulator's ARW and ADC-noise deviates of a chunk).
  friend void fill_both(normal_stream& sa, double* a, normal_stream& sb, double* b,
                        std::size_t n) noexcept {
    rng ga = sa.g_;
    rng gb = sb.g_;
    const detail::ziggurat_tables& z = *sa.z_;
    for (std::size_t k = 0; k < n; ++k) {
      a[k] = normal(ga, z);
      b[k] = normal(gb, z);
    }
    sa.g_ = ga;
    sb.g_ = gb;
  }

 private:
  rng g_;
  const detail::ziggurat_tables* z_;
};

}  // namespace gyroflip::sensor
