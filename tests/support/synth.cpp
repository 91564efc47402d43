#include "support/synth.hpp"

#include <cmath>
#include <numbers>

#include "gyroflip/sensor/gyro.hpp"

#include <fmt/format.h>

namespace gyroflip::test {

std::vector<double> static_gyro_rates(double arw_dps_rthz, double b_dps, double k_dps_rts,
                                      double bandwidth_hz, double dt_s, std::size_t n,
                                      std::uint64_t seed, double line_dps, double line_hz) {
  sensor::sensor_params p;
  p.arw_dps_rthz = arw_dps_rthz;
  p.bias_instability_dps = b_dps;
  p.flicker_tau_min_s = 2.0 * dt_s;  // flicker down to the shortest taus fitted
  p.flicker_tau_max_s = 1e4;
  p.rrw_dps_per_rts = k_dps_rts;
  p.bandwidth_hz = bandwidth_hz;
  p.range_dps = 1e6;  // never saturates
  auto g = sensor::gyro::make(p, dt_s, 0.0, seed);
  std::vector<double> y(n);
  if (!g) return {};
  const double phase = 0.7 * static_cast<double>(seed % 9);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = (static_cast<double>(k) + 0.5) * dt_s;
    const double line = line_dps * std::sin(2.0 * std::numbers::pi * line_hz * t + phase);
    y[k] = g->sample(t, p.temp_ref_c, line).v_rel / p.scale_factor_v_per_dps;
  }
  return y;
}

std::vector<method::row> synth_rows(const synth_spec& s) {
  normal_source noise(s.seed);
  std::vector<method::row> rows;
  const auto value = [&](double t, int sign) {
    return sign * (s.delta_n_dps(t) + s.input_dps) + s.bias_dps(t) + s.noise_dps * noise();
  };
  for (std::size_t k = 0; k < s.dwells; ++k) {
    const int sign = ((k % 2 == 0) != s.start_at_180) ? 1 : -1;
    const int position = sign > 0 ? 0 : 1;  // the paper's table: 0 at 0 deg, 1 at 180 deg
    const double centre = s.t0_s + static_cast<double>(k) * s.dwell_spacing_s;
    if (s.conversions == 1) {
      rows.push_back({centre, position, value(centre, sign), s.temp_c, 1});
      continue;
    }
    // Conversions centred on the dwell time, then two "turning" rows with an empty angle.
    const double half = 0.5 * static_cast<double>(s.conversions - 1) * s.conversion_s;
    for (std::uint32_t i = 0; i < s.conversions; ++i) {
      const double t = centre - half + static_cast<double>(i) * s.conversion_s;
      rows.push_back({t, position, value(t, sign), s.temp_c, 1});
    }
    for (int i = 1; i <= 2; ++i) {
      const double t = centre + half + i * 0.1;
      rows.push_back({t, table_moving, 123.0, s.temp_c, 1});
    }
  }
  return rows;
}

std::string to_csv(const std::vector<method::row>& rows, bool with_temp) {
  std::string out = "# sensor: synthetic\n";
  out +=
      with_temp ? "time_s,angle_deg,rate_dps,temp_c,n_avg\n" : "time_s,angle_deg,rate_dps,n_avg\n";
  for (const auto& r : rows) {
    const std::string angle = r.position == table_moving ? std::string()
                              : r.position == 0          ? "0"
                                                         : "180";
    if (with_temp)
      out += fmt::format("{},{},{},{},{}\n", r.time_s, angle, r.rate_dps, r.temp_c, r.n_avg);
    else
      out += fmt::format("{},{},{},{}\n", r.time_s, angle, r.rate_dps, r.n_avg);
  }
  return out;
}

}  // namespace gyroflip::test
