/// \file
/// \brief Test-only overlapping Allan deviation (NIST SP1065 eqn 11, from rate samples).
/// Replace with gyroflip::analysis::oadev once the analysis module has landed on main.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

namespace gyroflip::test {

/// Overlapping ADEV of rate samples `y` (any unit) spaced `dt_s`, at tau = m dt:
/// sigma^2 = sum_i (x_{i+2m} - 2 x_{i+m} + x_i)^2 / (2 tau^2 (M - 2m)), x = integrated angle
/// (M + 1 points).
inline double oadev(const std::vector<double>& y, double dt_s, std::size_t m) {
  std::vector<double> x(y.size() + 1, 0.0);
  for (std::size_t i = 0; i < y.size(); ++i) x[i + 1] = x[i] + y[i] * dt_s;
  const std::size_t n = x.size();
  if (n < 2 * m + 1) return NAN;
  double sum = 0.0;
  for (std::size_t i = 0; i + 2 * m < n; ++i) {
    const double d = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
    sum += d * d;
  }
  const double tau = static_cast<double>(m) * dt_s;
  return std::sqrt(sum / (2.0 * tau * tau * static_cast<double>(n - 2 * m)));
}

}  // namespace gyroflip::test
