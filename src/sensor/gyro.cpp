/// \file
/// \brief Construction of the gyro model (per-sample work is inline in the header).
#include "gyroflip/sensor/gyro.hpp"

#include <cmath>

#include "gyroflip/core/error.hpp"

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
      inv_dt_(1.0 / dt),
      chain_(p, dt),
      g0_{p.g_sens_x_dps_per_g, p.g_sens_y_dps_per_g, p.g_sens_z_dps_per_g},
      g1_{p.g_sens_tc_x_dps_per_g_c, p.g_sens_tc_y_dps_per_g_c, p.g_sens_tc_z_dps_per_g_c},
      arw_(seed, stream::angle_random_walk),
      slow_(p, power_on_before_s, seed) {
  if (p.turn_on_bias_sigma_dps > 0.0) {
    normal_stream turn_on(seed, stream::turn_on_bias);
    turn_on_dps_ = p.turn_on_bias_sigma_dps * turn_on.next();
  }
  bias0_dps_ = p.bias_dps + turn_on_dps_;
  // Its own stream, so that a preset without it draws exactly what it drew before.
  if (p.g_sens_turn_on_sigma_dps_per_g > 0.0 || p.g_sens_tc_turn_on_sigma_dps_per_g_c > 0.0) {
    normal_stream turn_on(seed, stream::turn_on_g_sensitivity);
    g0_.z += p.g_sens_turn_on_sigma_dps_per_g * turn_on.next();
    g1_.z += p.g_sens_tc_turn_on_sigma_dps_per_g_c * turn_on.next();
  }
}

void gyro::sample_block(const double* t_s, const double* temp_c, const double* rate_dps,
                        const double* n_arw, double* v_rel, double* bias_dps,
                        std::size_t n) noexcept {
  slow_.mean_block(t_s, half_dt_, inv_dt_, bias_dps, n);
  if (chain_.lpf_on()) {
    if (chain_.quant_on())
      return chain_block<true, true>(temp_c, rate_dps, n_arw, v_rel, bias_dps, n);
    return chain_block<true, false>(temp_c, rate_dps, n_arw, v_rel, bias_dps, n);
  }
  if (chain_.quant_on())
    return chain_block<false, true>(temp_c, rate_dps, n_arw, v_rel, bias_dps, n);
  return chain_block<false, false>(temp_c, rate_dps, n_arw, v_rel, bias_dps, n);
}

template <bool lpf, bool quant>
void gyro::chain_block(const double* __restrict temp_c, const double* __restrict rate_dps,
                       const double* __restrict n_arw, double* __restrict v_rel,
                       double* __restrict bias_dps, std::size_t n) noexcept {
  detail::output_chain::state s = state_;
  for (std::size_t i = 0; i < n; ++i) {  // the same operations in the same order as sample()
    const double dtemp = temp_c[i] - temp_ref_c_;
    const double bias = bias0_dps_ + bias_dps[i] + bias_tc_ * dtemp;
    bias_dps[i] = bias;
    v_rel[i] = chain_.output<lpf, quant>(s, rate_dps[i] + bias + arw_sigma_ * n_arw[i], dtemp);
  }
  state_ = s;
}

}  // namespace gyroflip::sensor
