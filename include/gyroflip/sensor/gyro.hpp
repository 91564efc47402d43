/// \file
/// \brief The single-axis gyro: from the true rate along its sensed direction to the output
/// voltage, one ADC conversion window at a time.
///
/// Per conversion k of length dt (the sample is the mean over the window):
///
///     b_k  = bias_dps + b_turn_on + mean of slow_bias over the window + bias_tc (T_k - T_ref)
///                                                                               (no reversal)
///     x_k  = w_k + b_k + N/sqrt(dt) n_k                  w_k = input + Earth + g-term (rig)
///     l_k  = a l_{k-1} + (1 - a) x_k,  a = e^{-2 pi f_c dt}    first-order low-pass, exact
///                                       for a piecewise-constant input (zero-order hold)
///     u_k  = (1 + e_sf + tc_sf (T_k - T_ref)) (l_k + (nl/range) l_k^2)   scale factor, bow
///     s_k  = clamp(u_k, -range, +range)                                 saturation
///     q_k  = (Q round(theta_k/Q) - Q round(theta_{k-1}/Q)) / dt,  theta_k = theta_{k-1} + s_k dt
///                                       angle quantisation (IEEE 952 Q: ADEV = sqrt(3) Q/tau)
///     V_k - V_null = SF_nominal q_k
///
/// The white-noise step N/sqrt(dt) is the exact mean of white rate noise of two-sided density
/// N^2 over dt (IEEE Std 952-1997 Annex C: ADEV = N/sqrt(tau)); its Allan deviation therefore
/// does not depend on dt. The g-term (g0 + g1 (T - T_ref)) . f is computed by the rig, which
/// knows the specific force f in sensor axes; `g_sens_g0`/`g_sens_g1` give the vectors.
#pragma once

#include <cmath>
#include <cstdint>

#include "gyroflip/core/result.hpp"
#include "gyroflip/sensor/detail/output_chain.hpp"
#include "gyroflip/sensor/error_terms.hpp"
#include "gyroflip/sensor/params.hpp"
#include "gyroflip/sensor/random.hpp"

namespace gyroflip::sensor {

/// A vector in sensor axes (x = sensitive axis).
struct sensor_vec {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

/// One conversion's output: the voltage relative to the nominal null (V) and the true bias.
struct gyro_sample {
  double v_rel = 0.0;     ///< V - null_v (V)
  double bias_dps = 0.0;  ///< b_k above (deg/s)
};

class gyro {
 public:
  /// `sample_period_s` = dt (s, > 0); `power_on_before_s` = how long the sensor has been on at
  /// t = 0 (s, >= 0; 0 = switched on at the start, paper Fig. 3); `seed` selects all streams.
  /// Errors: invalid parameters (validate()), dt <= 0, power-on time < 0.
  [[nodiscard]] static result<gyro> make(const sensor_params& p, double sample_period_s,
                                         double power_on_before_s, std::uint64_t seed);

  /// One conversion window [t_s - dt/2, t_s + dt/2] (t_s >= dt/2, non-decreasing), temperature
  /// `temp_c` (degC), true sensed rate `rate_dps` = input + Earth + g-term (deg/s).
  gyro_sample sample(double t_s, double temp_c, double rate_dps) noexcept {
    return sample(t_s, temp_c, rate_dps, arw_on_ ? arw_.next() : 0.0);
  }

  /// The same with the ARW deviate `n_arw` ~ N(0,1) supplied by the caller, who drew it from
  /// arw_stream() (batch generation in the simulator; identical results).
  gyro_sample sample(double t_s, double temp_c, double rate_dps, double n_arw) noexcept {
    const double dtemp = temp_c - temp_ref_c_;
    const double bias = bias0_dps_ + slow_.mean_at(t_s, half_dt_, inv_dt_) + bias_tc_ * dtemp;
    const double x = rate_dps + bias + arw_sigma_ * n_arw;
    const double v = chain_.output(state_, x, dtemp);
    return {v, bias};
  }

  /// `n` conversions at once, bit-identical to n calls of sample(): `t_s`, `temp_c`, `rate_dps`
  /// as above and the ARW deviates `n_arw` in; voltages (V - null) and true biases out. The
  /// slow-bias means come first (one tight loop per grid interval), then one fused loop runs
  /// the whole per-conversion chain: the low-pass recursion is a chain of dependent operations,
  /// and the rest of the chain executes in its shadow instead of in loops of its own.
  void sample_block(const double* t_s, const double* temp_c, const double* rate_dps,
                    const double* n_arw, double* v_rel, double* bias_dps, std::size_t n) noexcept;

  /// g0 (deg/s/g) and g1 (deg/s/g/degC) in sensor axes.
  [[nodiscard]] sensor_vec g_sens_g0() const noexcept { return g0_; }
  [[nodiscard]] sensor_vec g_sens_g1() const noexcept { return g1_; }
  [[nodiscard]] double temp_ref_c() const noexcept { return temp_ref_c_; }
  /// The per-power-up bias drawn for this run (deg/s).
  [[nodiscard]] double turn_on_bias_dps() const noexcept { return turn_on_dps_; }
  [[nodiscard]] const sensor_params& params() const noexcept { return p_; }
  /// The ARW stream (for batch generation) and whether ARW is on.
  [[nodiscard]] normal_stream& arw_stream() noexcept { return arw_; }
  [[nodiscard]] bool arw_on() const noexcept { return arw_on_; }

 private:
  gyro(const sensor_params& p, double dt, double power_on_before_s, std::uint64_t seed);
  template <bool lpf, bool quant>
  void chain_block(const double* temp_c, const double* rate_dps, const double* n_arw, double* v_rel,
                   double* bias_dps, std::size_t n) noexcept;
  sensor_params p_;
  double half_dt_;
  double temp_ref_c_, bias0_dps_ = 0.0, turn_on_dps_ = 0.0, bias_tc_;
  bool arw_on_;
  double arw_sigma_;
  double inv_dt_;  // 1/dt
  detail::output_chain chain_;
  detail::output_chain::state state_;
  sensor_vec g0_, g1_;
  normal_stream arw_;
  slow_bias slow_;
};

}  // namespace gyroflip::sensor
