/// \file
/// \brief The simulator's random numbers: xoshiro256** seeded through splitmix64, one
/// independent stream per error term, and a ziggurat normal generator of our own.
///
/// `std::normal_distribution` is implementation-defined (libstdc++ and libc++ give different
/// numbers), so it is never used: the same seed gives the same recording on any machine.
/// Streams are derived from (seed, stream id), so turning one error term off leaves the random
/// numbers of all other terms unchanged.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
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

/// Ziggurat tables (256 layers, Marsaglia & Tsang 2000, r = 3.6541528853610088,
/// v = 4.92867323399e-3), built once with det_exp/det_log (Doornik 2005 "ZIGNOR" layout:
/// x[0] = v/f(r), x[1] = r, x[i+1] = sqrt(-2 ln(v/x[i] + f(x[i]))), x[256] = 0,
/// ratio[i] = x[i+1]/x[i], f[i] = exp(-x[i]^2/2)). The fast path tests and scales the 53-bit
/// integer s behind u = s 2^-52 directly: |u| < ratio[i] <=> |s| < k_i = ceil(ratio[i] 2^52)
/// <=> (unsigned)(s + shift[i]) <= span[i] (shift = k - 1, span = 2k - 2; k = 0 never
/// accepts), and u x[i] = s (x[i] 2^-52) exactly as rounded (scaling by 2^-52 is exact), so the
/// numbers are those of the textbook test on doubles, with one compare on integers.
struct ziggurat_tables {
  std::array<double, 257> x{};
  std::array<double, 256> ratio{};
  std::array<double, 257> f{};
  std::array<std::uint64_t, 256> shift{}, span{};
  std::array<double, 256> x_scaled{};  // x[i] 2^-52
  // Wedge i (x[i+1] <= |x| <= x[i]): +1 where the density is convex there (x[i+1] >= 1), -1
  // where concave (x[i] <= 1), 0 across x = 1; and the slope of its chord.
  std::array<int, 256> curvature{};
  std::array<double, 256> chord_slope{};
};
[[nodiscard]] const ziggurat_tables& ziggurat();

/// Tail beyond r (Marsaglia 1964): x = -ln(U1)/r, y = -ln(U2) until 2y > x^2; returns r + x.
[[nodiscard]] double normal_tail(rng& g) noexcept;

/// The wedge test of layer i >= 1: is the point (|x| = `ax`, height `y`) under the density
/// e^{-x^2/2}? First without exp, from bounds that hold on the wedge (Marsaglia & Tsang 2000
/// sec. 3 use the chord likewise): where the density is convex it lies under the chord and
/// above both end tangents, where concave the other way round; a point outside the band
/// between the bounds by more than 1e-12 (relative; the bounds' rounding is ~1e-15) is decided
/// at once. Only points inside the band (and wedges across x = 1) take det_exp. The answer is
/// that of det_exp except within its own rounding of the curve.
[[nodiscard]] bool wedge_accepts(const ziggurat_tables& z, std::size_t i, double ax,
                                 double y) noexcept;

/// The deviate and the generator state after the rare part of `normal`.
struct slow_normal {
  double value;
  rng state;
};

/// The rare part of `normal`: the wedge test for (layer i, signed uniform u) already drawn,
/// the tail for i = 0, and on rejection further draws until acceptance. Out of line so that
/// the fast path stays small; the generator goes in and comes back by value, so that in the
/// caller's loop its state never has to live in memory (a reference would pin it there).
[[nodiscard]] slow_normal normal_slow(rng g, const ziggurat_tables& z, std::size_t i,
                                      double u) noexcept;

/// A standard normal N(0, 1) deviate. Fast path (98.8 %): one 64-bit number, one multiply,
/// one compare; low 8 bits pick the layer, the top 53 bits the signed uniform (disjoint bits,
/// so no layer/value correlation, Doornik 2005 section 4).
[[nodiscard]] inline double normal(rng& g, const ziggurat_tables& z) noexcept {
  const std::uint64_t r = g.next();
  const auto i = static_cast<std::size_t>(r & 0xffU);
  const std::int64_t s53 = static_cast<std::int64_t>(r) >> 11;  // in [-2^52, 2^52)
  if (static_cast<std::uint64_t>(s53) + z.shift[i] <= z.span[i]) [[likely]] {
    return static_cast<double>(s53) * z.x_scaled[i];
  }
  const double u = static_cast<double>(s53) * 0x1.0p-52;
  const slow_normal s = normal_slow(g, z, i, u);
  g = s.state;
  return s.value;
}

/// A normal stream: an `rng` plus the shared ziggurat tables (a value type, cheap to copy).
class normal_stream {
 public:
  normal_stream(std::uint64_t seed, stream id) : g_(seed, id), z_(&ziggurat()) {}
  /// N(0, 1).
  double next() noexcept { return normal(g_, *z_); }
  /// Fills `out[0..n)` with N(0, 1) (the same numbers as n calls of next(), but faster: a
  /// tight loop keeps the generator state in registers).
  void fill(double* out, std::size_t n) noexcept {
    rng g = g_;
    const ziggurat_tables& z = *z_;
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
    const ziggurat_tables& z = *sa.z_;
    for (std::size_t k = 0; k < n; ++k) {
      a[k] = normal(ga, z);
      b[k] = normal(gb, z);
    }
    sa.g_ = ga;
    sb.g_ = gb;
  }

 private:
  rng g_;
  const ziggurat_tables* z_;
};

}  // namespace gyroflip::sensor
