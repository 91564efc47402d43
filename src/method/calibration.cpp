/// \file
/// \brief dN calibration statistics (see calibration.hpp).
#include "gyroflip/method/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/drift.hpp"
#include "gyroflip/core/error.hpp"

namespace gyroflip::method {

correlated_error correlated_stderr(std::span<const double> y, double naive_stderr) {
  constexpr std::size_t min_series = 16;  // m* = n/8 >= 2 cycles
  const std::size_t n = y.size();
  if (n < min_series) return {naive_stderr, 0, false};
  const std::size_t m = n / 8;
  // Overlapping Allan variance of the cycle series at m* (NIST SP1065 eqn 11), unit spacing.
  const double adev =
      analysis::deviation_at(analysis::dev_kind::oadev, analysis::phase_from_rate(y, 1.0), 1.0, m)
          .dev;
  const double var_mean = adev * adev * static_cast<double>(m) / static_cast<double>(n);
  return {std::sqrt(std::max(naive_stderr * naive_stderr, var_mean)), m, true};
}

result<calibration> calibrate(std::span<const cycle> cycles) {
  if (cycles.size() < min_cycles)
    return runtime_error(fmt::format("{} cycle{} found; calibration needs at least {}",
                                     cycles.size(), cycles.size() == 1 ? "" : "s", min_cycles));
  std::vector<double> r(cycles.size());
  std::vector<double> c(cycles.size());
  double temp_sum = 0.0;
  std::size_t temp_n = 0;
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    r[i] = cycles[i].rate_dps;
    c[i] = cycles[i].bias_dps;
    if (!std::isnan(cycles[i].temp_c)) {
      temp_sum += cycles[i].temp_c;
      ++temp_n;
    }
  }
  const auto s = analysis::mean_and_std(r);
  calibration cal;
  cal.delta_n_dps = s.mean;
  cal.std_dps = s.std;
  cal.cycles = s.n;
  cal.stderr_dps = s.std / std::sqrt(static_cast<double>(s.n));
  const auto ce = correlated_stderr(r, cal.stderr_dps);
  cal.stderr_correlated_dps = ce.stderr_dps;
  cal.correlated_m = ce.m;
  cal.temp_c = temp_n > 0 ? temp_sum / static_cast<double>(temp_n) : no_value;
  cal.duration_s = cycles.back().time_s - cycles.front().time_s;
  cal.bias_mean_dps = analysis::mean_and_std(c).mean;
  return cal;
}

delta_n_split split_delta_n(double delta_n_dps, double lat_deg, const earth::ned_vector& axis) {
  const double w = earth::earth_rate_component_dps(lat_deg, axis);
  return {w, delta_n_dps - w};
}

}  // namespace gyroflip::method
