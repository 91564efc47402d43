/// \file
/// \brief Internal to `sensor::gyro`: the per-conversion output chain (low-pass, scale factor and
/// bow, saturation, angle quantisation, nominal scale factor), inline so that the simulator's
/// block loop keeps it in registers. Formulas: gyro.hpp. Not part of the public API.
#pragma once

#include "gyroflip/sensor/det_math.hpp"
#include "gyroflip/sensor/params.hpp"

namespace gyroflip::sensor::detail {

class output_chain {
 public:
  /// The states of the low-pass and the quantiser (callers copy them to locals in block loops,
  /// so that they stay in registers).
  struct state {
    double lpf = 0.0;      // l_{k-1} (deg/s)
    double theta = 0.0;    // accumulated angle (in quanta Q: rounding is then one step)
    double theta_q = 0.0;  // its rounded value at the previous conversion (quanta)
    bool first = true;     // the low-pass starts at its first input
  };

  /// Coefficients for sensor `p` and conversion time `dt_s` (s, > 0; checked by gyro::make).
  output_chain(const sensor_params& p, double dt_s) noexcept
      : lpf_on_(p.bandwidth_hz > 0.0),
        quant_on_(p.quantisation_deg > 0.0),
        nl_per_dps_(p.nonlinearity_fs / p.range_dps),
        sf_ratio_(1.0 + 1e-6 * p.scale_factor_error_ppm),
        sf_tc_(1e-6 * p.scale_factor_tc_ppm_per_c),
        range_dps_(p.range_dps),
        dt_per_quantum_(quant_on_ ? dt_s / p.quantisation_deg : 0.0),
        quantum_v_(p.quantisation_deg * p.scale_factor_v_per_dps / dt_s),
        sf_v_per_dps_(p.scale_factor_v_per_dps) {
    constexpr double two_pi = 6.28318530717958647692;
    if (lpf_on_) {
      lpf_keep_ = det_exp(-two_pi * p.bandwidth_hz * dt_s);
      lpf_gain_ = 1.0 - lpf_keep_;
    }
  }

  [[nodiscard]] bool lpf_on() const noexcept { return lpf_on_; }
  [[nodiscard]] bool quant_on() const noexcept { return quant_on_; }

  /// From x_k = input + bias + ARW (deg/s) to V - V_null (V), `dtemp` = T - T_ref (degC). The two
  /// optional stages are template switches, so a block loop has no per-sample test for them.
  template <bool lpf, bool quant>
  double output(state& s, double x, double dtemp) const noexcept {
    if constexpr (lpf) {
      if (s.first) [[unlikely]] {  // the filter starts at its first input
        s.lpf = x;
        s.first = false;
      }
      s.lpf = lpf_keep_ * s.lpf + lpf_gain_ * x;  // two dependent operations per conversion
      x = s.lpf;
    }
    x = (x + nl_per_dps_ * x * x) * (sf_ratio_ + sf_tc_ * dtemp);
    x = x < range_dps_ ? x : range_dps_;  // saturation as min and max (two instructions)
    x = x > -range_dps_ ? x : -range_dps_;
    if constexpr (quant) {
      s.theta += x * dt_per_quantum_;  // theta_k / Q, exact below 2^51 quanta
      const double q = round_even(s.theta);
      x = q - s.theta_q;
      s.theta_q = q;
      return x * quantum_v_;  // (q_k - q_{k-1}) Q / dt * SF
    }
    return x * sf_v_per_dps_;
  }

  /// `output` with the stages chosen at run time (one conversion at a time).
  double output(state& s, double x, double dtemp) const noexcept {
    if (lpf_on_)
      return quant_on_ ? output<true, true>(s, x, dtemp) : output<true, false>(s, x, dtemp);
    return quant_on_ ? output<false, true>(s, x, dtemp) : output<false, false>(s, x, dtemp);
  }

 private:
  bool lpf_on_;
  bool quant_on_;
  double lpf_keep_ = 0.0, lpf_gain_ = 1.0;  // a = e^{-2 pi f_c dt} and 1 - a
  double nl_per_dps_, sf_ratio_, sf_tc_, range_dps_;
  double dt_per_quantum_, quantum_v_;  // dt/Q (s/deg), Q SF/dt (V)
  double sf_v_per_dps_;
};

}  // namespace gyroflip::sensor::detail
