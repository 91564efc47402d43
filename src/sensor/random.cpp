/// \file
/// \brief Ziggurat tables and the rare branches of the normal generator.
#include "gyroflip/sensor/random.hpp"

#include <cmath>

#include "gyroflip/sensor/det_math.hpp"

namespace gyroflip::sensor {
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

double ziggurat_density_ratio(double a, double x) noexcept {
  return det_exp(-0.5 * (a * a - x * x));
}

}  // namespace gyroflip::sensor
