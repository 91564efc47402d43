/// \file
/// \brief Ziggurat tables and the rare branches of the normal generator.
#include "gyroflip/sensor/random.hpp"

#include <algorithm>
#include <cmath>

#include "gyroflip/sensor/det_math.hpp"

namespace gyroflip::sensor::detail {
namespace {

constexpr double zig_r = 3.6541528853610088;
constexpr double zig_v = 4.92867323399e-3;

ziggurat_tables build() {
  ziggurat_tables t;
  double f = det_exp(-0.5 * zig_r * zig_r);
  t.x[0] = zig_v / f;
  t.x[1] = zig_r;
  for (std::size_t i = 2; i < 256; ++i) {
    t.x[i] = std::sqrt(-2.0 * det_log(zig_v / t.x[i - 1] + f));
    f = det_exp(-0.5 * t.x[i] * t.x[i]);
  }
  t.x[256] = 0.0;
  for (std::size_t i = 0; i < 256; ++i) t.ratio[i] = t.x[i + 1] / t.x[i];
  for (std::size_t i = 0; i <= 256; ++i) t.f[i] = det_exp(-0.5 * t.x[i] * t.x[i]);
  for (std::size_t i = 0; i < 256; ++i) {
    const auto k = static_cast<std::uint64_t>(std::ceil(t.ratio[i] * 0x1.0p52));
    t.shift[i] = k == 0 ? std::uint64_t{1} << 62 : k - 1;  // k = 0: s + 2^62 > 0 = span
    t.span[i] = k == 0 ? 0 : 2 * k - 2;
    t.x_scaled[i] = t.x[i] * 0x1.0p-52;
  }
  for (std::size_t i = 1; i < 256; ++i) {
    t.curvature[i] = t.x[i + 1] >= 1.0 ? 1 : (t.x[i] <= 1.0 ? -1 : 0);  // f'' = (x^2 - 1) f
    t.chord_slope[i] = (t.f[i] - t.f[i + 1]) / (t.x[i] - t.x[i + 1]);
  }
  return t;
}

}  // namespace

const ziggurat_tables& ziggurat() {
  static const ziggurat_tables tables = build();  // immutable constants, built once
  return tables;
}

double normal_tail(rng& g) noexcept {
  for (;;) {
    const double x = -det_log(g.uniform_open()) / zig_r;
    const double y = -det_log(g.uniform_open());
    if (2.0 * y > x * x) return zig_r + x;
  }
}

bool wedge_accepts(const ziggurat_tables& z, std::size_t i, double ax, double y) noexcept {
  constexpr double margin = 1e-12;
  const double a = z.x[i + 1];
  const double b = z.x[i];
  const double chord = z.f[i + 1] + (ax - a) * z.chord_slope[i];
  const double tangent_a = z.f[i + 1] * (1.0 - a * (ax - a));  // f'(x) = -x f(x)
  const double tangent_b = z.f[i] * (1.0 - b * (ax - b));
  if (z.curvature[i] > 0) {  // tangents <= f <= chord
    if (y >= chord * (1.0 + margin)) return false;
    if (y < std::max(tangent_a, tangent_b) * (1.0 - margin)) return true;
  } else if (z.curvature[i] < 0) {  // chord <= f <= tangents
    if (y < chord * (1.0 - margin)) return true;
    if (y >= std::min(tangent_a, tangent_b) * (1.0 + margin)) return false;
  }
  return y < det_exp(-0.5 * ax * ax);
}

slow_normal normal_slow(rng g, const ziggurat_tables& z, std::size_t i, double u) noexcept {
  for (;;) {
    if (i == 0) {
      const double t = normal_tail(g);
      return {u < 0.0 ? -t : t, g};
    }
    // Wedge between layers i and i+1: accept x when a uniform height between the layers' densities
    // lies under the density (Marsaglia & Tsang 2000; one exp with the tabulated f[i]).
    const double xv = u * z.x[i];
    if (wedge_accepts(z, i, std::fabs(xv), z.f[i + 1] + g.uniform_open() * (z.f[i] - z.f[i + 1])))
      return {xv, g};
    const std::uint64_t r = g.next();  // rejected: draw again
    i = static_cast<std::size_t>(r & 0xffU);
    u = static_cast<double>(static_cast<std::int64_t>(r) >> 11) * 0x1.0p-52;
    if (std::fabs(u) < z.ratio[i]) return {u * z.x[i], g};
  }
}

}  // namespace gyroflip::sensor::detail
