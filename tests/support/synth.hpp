/// \file
/// \brief Synthetic flip recordings with known truth, for tests (not the simulator: no sensor
/// physics, just y = s*(dN(t,T) + w_in) + b(t) + noise at dwell or conversion level).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "gyroflip/method/types.hpp"
#include "gyroflip/sensor/random.hpp"

namespace gyroflip::test {

struct synth_spec {
  std::size_t dwells = 120;
  double t0_s = 0.256;
  double dwell_spacing_s = 0.895;  ///< time between dwell centres (paper: 1.79 s per cycle)
  std::function<double(double)> delta_n_dps = [](double) { return 0.0123; };  ///< dN(t)
  std::function<double(double)> bias_dps = [](double) { return 0.5; };        ///< b(t)
  double input_dps = 0.0;  ///< w_in (reverses with the flip)
  double temp_c = 20.0;    ///< NaN: no temperature column
  double noise_dps = 0.0;  ///< white noise per row
  std::uint64_t seed = 1;
  bool start_at_180 = false;
  std::uint32_t conversions = 1;  ///< >1: raw rows (n_avg = 1) per dwell, with turning rows
  double conversion_s = 0.002;
};

/// Rows of the synthetic recording.
std::vector<method::row> synth_rows(const synth_spec& s);

/// CSV text of rows (columns time_s,angle_deg,rate_dps[,temp_c],n_avg; `# ` metadata first).
std::string to_csv(const std::vector<method::row>& rows, bool with_temp);

/// A static gyro record through the simulator's sensor (sensor/gyro.hpp): `n` rate samples
/// (deg/s) every `dt_s` of a sensor with noise terms N (`arw_dps_rthz`), B (`b_dps`, its
/// Gauss-Markov flicker bank from 2 dt to 1e4 s, so that
/// its floor holds at every tau fitted), K (`k_dps_rts`) and a first-order low-pass of
/// corner `bandwidth_hz` (0: none), at rest at its reference temperature, plus a sinusoid of
/// amplitude `line_dps` at `line_hz` (a spectral line; 0: none). Known truth for the noise fit.
std::vector<double> static_gyro_rates(double arw_dps_rthz, double b_dps, double k_dps_rts,
                                      double bandwidth_hz, double dt_s, std::size_t n,
                                      std::uint64_t seed, double line_dps = 0.0,
                                      double line_hz = 0.0);

/// A deterministic N(0,1) source: the simulator's generator on its first free stream
/// (sensor/random.hpp; never std::normal_distribution, which differs between platforms).
class normal_source {
 public:
  explicit normal_source(std::uint64_t seed) : s_(seed, sensor::stream::user) {}
  double operator()() { return s_.next(); }

 private:
  sensor::normal_stream s_;
};

}  // namespace gyroflip::test
