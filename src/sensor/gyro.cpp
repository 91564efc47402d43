/// \file
/// \brief Construction of the gyro model (per-sample work is inline in the header).
#include "gyroflip/sensor/gyro.hpp"

#include <cmath>

#include "gyroflip/core/error.hpp"
#include "gyroflip/sensor/det_math.hpp"

namespace gyroflip::sensor {

result<gyro> gyro::make(const sensor_params& p, double sample_period_s, double power_on_before_s,
                        std::uint64_t seed) {
  if (auto s = validate(p); !s) return s.err();
  if (!(sample_period_s > 0.0) || !std::isfinite(sample_period_s)) {
    return usage_error("sample period must be positive");
  }
  if (!(power_on_before_s >= 0.0) || !std::isfinite(power_on_before_s)) {
    return usage_error("power-on time before the run must be >= 0 s");
  }
  return gyro(p, sample_period_s, power_on_before_s, seed);
}

gyro::gyro(const sensor_params& p, double dt, double power_on_before_s, std::uint64_t seed)
    : p_(p),
      half_dt_(0.5 * dt),
      temp_ref_c_(p.temp_ref_c),
      bias_tc_(p.bias_tc_dps_per_c),
      arw_on_(p.arw_dps_rthz > 0.0),
      arw_sigma_(p.arw_dps_rthz / std::sqrt(dt)),
      lpf_on_(p.bandwidth_hz > 0.0),
      nl_per_dps_(p.nonlinearity_fs / p.range_dps),
      sf_ratio_(1.0 + 1e-6 * p.scale_factor_error_ppm),
      sf_tc_(1e-6 * p.scale_factor_tc_ppm_per_c),
      range_dps_(p.range_dps),
      quant_on_(p.quantisation_deg > 0.0),
      inv_dt_(1.0 / dt),
      dt_per_quantum_(p.quantisation_deg > 0.0 ? dt / p.quantisation_deg : 0.0),
      quantum_v_(p.quantisation_deg * p.scale_factor_v_per_dps / dt),
      sf_v_per_dps_(p.scale_factor_v_per_dps),
      g0_{p.g_sens_x_dps_per_g, p.g_sens_y_dps_per_g, p.g_sens_z_dps_per_g},
      g1_{p.g_sens_tc_x_dps_per_g_c, p.g_sens_tc_y_dps_per_g_c, p.g_sens_tc_z_dps_per_g_c},
      arw_(seed, stream::angle_random_walk),
      slow_(p, power_on_before_s, seed) {
  constexpr double two_pi = 6.28318530717958647692;
  if (lpf_on_) {
    lpf_keep_ = det_exp(-two_pi * p.bandwidth_hz * dt);
    lpf_gain_ = 1.0 - lpf_keep_;
  }
  if (p.turn_on_bias_sigma_dps > 0.0) {
    normal_stream turn_on(seed, stream::turn_on_bias);
    turn_on_dps_ = p.turn_on_bias_sigma_dps * turn_on.next();
  }
  bias0_dps_ = p.bias_dps + turn_on_dps_;
}

void gyro::sample_block(const double* t_s, const double* temp_c, const double* rate_dps,
                        const double* n_arw, double* v_rel, double* bias_dps,
                        std::size_t n) noexcept {
  slow_.mean_block(t_s, half_dt_, inv_dt_, bias_dps, n);
  if (lpf_on_) {
    if (quant_on_) return chain_block<true, true>(temp_c, rate_dps, n_arw, v_rel, bias_dps, n);
    return chain_block<true, false>(temp_c, rate_dps, n_arw, v_rel, bias_dps, n);
  }
  if (quant_on_) return chain_block<false, true>(temp_c, rate_dps, n_arw, v_rel, bias_dps, n);
  return chain_block<false, false>(temp_c, rate_dps, n_arw, v_rel, bias_dps, n);
}

template <bool lpf, bool quant>
void gyro::chain_block(const double* __restrict temp_c, const double* __restrict rate_dps,
                       const double* __restrict n_arw, double* __restrict v_rel,
                       double* __restrict bias_dps, std::size_t n) noexcept {
  chain_state s = state_;
  for (std::size_t i = 0; i < n; ++i) {  // the same operations in the same order as sample()
    const double dtemp = temp_c[i] - temp_ref_c_;
    const double bias = bias0_dps_ + bias_dps[i] + bias_tc_ * dtemp;
    bias_dps[i] = bias;
    v_rel[i] = output<lpf, quant>(s, rate_dps[i] + bias + arw_sigma_ * n_arw[i], dtemp);
  }
  state_ = s;
}

}  // namespace gyroflip::sensor
