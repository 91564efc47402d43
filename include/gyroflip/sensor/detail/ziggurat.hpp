/// \file
/// \brief Internal to the normal generator of sensor/random.hpp: the ziggurat tables and the rare
/// paths (wedge, tail) that `sensor::normal` takes out of line. Not part of the public API; the
/// tests reach in to check the tables against the density.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "gyroflip/sensor/rng.hpp"

namespace gyroflip::sensor::detail {

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

}  // namespace gyroflip::sensor::detail
