/// \file
/// \brief `sensor_params`: every figure of the single-axis gyro model, with units, and a
/// table describing each field (key, unit, meaning) for presets, TOML files and `sensors`.
///
/// Sensor axes: x is the sensitive axis; y and z complete a right-handed frame (the rig module
/// fixes them: at the table's 0 deg position y is the table axis when it is perpendicular to x).
/// The model itself (equations, sources) is in sensor/gyro.hpp and docs/SIMULATOR.md.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "gyroflip/core/result.hpp"

namespace gyroflip::sensor {

struct sensor_params {
  // Output chain.
  double range_dps = 150.0;                ///< saturation of the sensed rate (deg/s)
  double scale_factor_v_per_dps = 0.0125;  ///< nominal scale factor (V per deg/s)
  double null_v = 2.5;                     ///< nominal null (zero-rate) output voltage (V)
  double bandwidth_hz = 40.0;              ///< first-order low-pass corner (Hz), 0 = none
  double scale_factor_error_ppm = 0.0;     ///< actual/nominal scale factor - 1 (ppm)
  double scale_factor_tc_ppm_per_c = 0.0;  ///< scale-factor temperature coefficient (ppm/degC)
  double nonlinearity_fs = 0.0;            ///< quadratic bow, fraction of full scale at +-range (-)
  double quantisation_deg = 0.0;           ///< angle quantum Q of a digital output (deg), 0 = none
  // Noise (IEEE Std 952-1997 Annex C coefficients).
  double arw_dps_rthz = 0.0;          ///< angle random walk N: ADEV(tau) = N/sqrt(tau) (deg/s/rtHz)
  double bias_instability_dps = 0.0;  ///< flicker coefficient B: ADEV floor = 0.6643 B (deg/s)
  double flicker_tau_min_s = 1.0;     ///< shortest Gauss-Markov time constant of the bank (s)
  double flicker_tau_max_s = 1.0e4;   ///< longest Gauss-Markov time constant of the bank (s)
  double rrw_dps_per_rts = 0.0;       ///< rate random walk K: ADEV = K sqrt(tau/3) (deg/s/rts)
  double rate_ramp_dps_per_s = 0.0;   ///< rate ramp R: bias grows R t (deg/s per s)
  // Bias (does not reverse with the flip).
  double bias_dps = 0.0;                ///< repeatable bias at temp_ref_c (deg/s)
  double turn_on_bias_sigma_dps = 0.0;  ///< std of the random bias drawn per power-up (deg/s)
  double warmup_amplitude_dps = 0.0;    ///< warm-up transient A e^{-t_on/tau_w} (deg/s)
  double warmup_tau_s = 600.0;          ///< warm-up time constant tau_w (s)
  double bias_tc_dps_per_c = 0.0;       ///< bias temperature coefficient (deg/s per degC)
  double temp_ref_c = 20.0;             ///< reference temperature of all coefficients (degC)
  // g-sensitivity: g_term = (g0 + g1 (T - T_ref)) . f, f = specific force in sensor axes (g).
  double g_sens_x_dps_per_g = 0.0;
  double g_sens_y_dps_per_g = 0.0;
  double g_sens_z_dps_per_g = 0.0;
  double g_sens_tc_x_dps_per_g_c = 0.0;
  double g_sens_tc_y_dps_per_g_c = 0.0;
  double g_sens_tc_z_dps_per_g_c = 0.0;
  // Per power-up (turn-on) changes of the g-sensitivity along z, the sensor axis the default rig
  // turns upside down, so that they change dN from run to run (paper Tab. 3/4: the runs' dN
  // scatter 14-30 times their own errors). Drawn once per run, like turn_on_bias_sigma_dps.
  double g_sens_turn_on_sigma_dps_per_g = 0.0;       ///< std of the change of g_sens_z
  double g_sens_tc_turn_on_sigma_dps_per_g_c = 0.0;  ///< std of the change of g_sens_tc_z
  // The g-sensitivity a specification states (not simulated: what a calibration's g-term is
  // checked against, method/stationarity.hpp). A guaranteed maximum ("< 0.06 deg/s/g") and a
  // typical value ("0.2 deg/s/g typ.") are different promises, so they are separate; 0 = not
  // stated.
  double g_sens_spec_max_dps_per_g = 0.0;  ///< guaranteed maximum |g-sensitivity| (deg/s/g)
  double g_sens_spec_typ_dps_per_g = 0.0;  ///< typical |g-sensitivity| (deg/s/g)
  // Cross-axis sensitivity: sensed rate = w_x + c_y w_y + c_z w_z.
  double cross_axis_y = 0.0;  ///< (-)
  double cross_axis_z = 0.0;  ///< (-)
};

/// One documented field of `sensor_params`.
struct field_info {
  std::string_view key;   ///< TOML / JSON key (= member name)
  std::string_view unit;  ///< unit text
  std::string_view what;  ///< one-line meaning
  double sensor_params::*member;
  double min_value;  ///< smallest valid value
  double max_value;  ///< largest valid value
};

/// All fields, in declaration order.
[[nodiscard]] std::span<const field_info> fields();

/// The field called `key`, or nullptr.
[[nodiscard]] const field_info* find_field(std::string_view key);

/// Checks every field is finite and within its [min, max], plus flicker_tau_min_s <
/// flicker_tau_max_s. The message names the key (the caller adds the position).
[[nodiscard]] status validate(const sensor_params& p);

}  // namespace gyroflip::sensor
