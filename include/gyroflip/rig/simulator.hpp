/// \file
/// \brief The recording generator: sensor on the turntable, read by the AD7739 on the
/// paper's schedule, with the truth of every term; and the per-dwell averaging of recordings.
///
/// Per conversion k (t_k = (k + 1/2) t_conv, the centre of the window) at cycle slot p:
///   w_k = w_in(t_k) u_p + table_p + earth_p + (g0 + g1 (T_k - T_ref)) . f_p
/// with u_p, table_p, earth_p, f_p the sensed input-axis gain, table rate, Earth rate and
/// specific force of slot p (rig/geometry.hpp, precomputed once per cycle slot since the cycle
/// repeats exactly). The gyro (sensor/gyro.hpp) turns w_k into a voltage, the AD7739 into a
/// code, and the recorder back into deg/s with the NOMINAL scale factor:
///   rate_k = (code_k - 2^23) LSB / SF_nominal.
/// The rate-table input rotates about the 0-deg sensitive-axis direction without changing the
/// rig's attitude to gravity and the Earth (its effect on the g- and Earth terms is neglected).
/// Truth columns are signed as seen by the sensor at that moment: at 180 deg the Earth term,
/// the g-term and the input have the opposite sign of 0 deg, the bias the same sign.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/rig/ad7739.hpp"
#include "gyroflip/rig/geometry.hpp"
#include "gyroflip/rig/profiles.hpp"
#include "gyroflip/rig/rig_config.hpp"
#include "gyroflip/rig/schedule.hpp"
#include "gyroflip/rig/turntable.hpp"
#include "gyroflip/sensor/gyro.hpp"

namespace gyroflip::rig {

/// Limits of a simulation (docs/SIMULATOR.md, "Limits"): beyond them the output would be
/// unbounded in size or not a physical rig.
inline constexpr double max_duration_s = 1e7;  ///< 116 days
inline constexpr double max_rate_dps = 1e6;    ///< input rate magnitude

/// The stepper's coils warm the table under the gyro while they are energised: a first-order
/// path, dT' = (rise_c on(t) - dT) / tau_s, added to the temperature profile (the gyro's
/// temperature, so its bias and g-sensitivity follow it). The device energises the coils while
/// the table turns and settles and, unless rig_config::hold_coils, not while the gyro measures
/// (docs/HARDWARE.md, "Stepper holding current"). rise_c 0: no heat path (the default: the
/// paper gives no figure; docs/SIMULATOR.md states the values its example assumes).
struct coil_heating {
  double rise_c = 0.0;   ///< steady rise with the coils on all the time (degC), 0..50
  double tau_s = 600.0;  ///< time constant of the table's warming (s), 1..1e6
  /// Errors (parameter "coil_heat"): a value outside the ranges above.
  [[nodiscard]] status check() const;
  /// The rise after `dt_s` more seconds from `rise_now_c`, the coils on or off meanwhile (the
  /// first-order step, exact for a constant state).
  [[nodiscard]] double step(double rise_now_c, bool on, double dt_s) const noexcept {
    return rise_now_c + ((on ? rise_c : 0.0) - rise_now_c) * -std::expm1(-dt_s / tau_s);
  }
};

struct simulation_config {
  sensor::sensor_params sensor;
  double lat_deg = 42.6;       ///< paper site, Sofia (deg)
  std::string axis = "north";  ///< sensitive axis at 0 deg (earth::parse_axis)
  std::string table_axis;      ///< empty = default (geometry.hpp)
  rig_mount mount;  ///< an azimuth for the sensitive axis, the table's tilt (geometry.hpp)
  visit_order order = visit_order::automatic;     ///< how the positions are visited (schedule.hpp)
  profile rate = profile::constant(0.0);          ///< input rate w_in (deg/s)
  profile temperature = profile::constant(20.0);  ///< sensor temperature (degC)
  rig_config rig;              ///< the rig's settings (the device's CONFIGURE; rig_config.hpp)
  bool flip = true;            ///< false: never turn, dwell after dwell at position A (raw sensor)
  ad7739_part adc;             ///< the ADC part (its filter word and chopping are the rig's)
  double duration_s = 3600.0;  ///< run length (s)
  double power_on_before_s = 0.0;  ///< sensor on this long before t = 0 (s)
  coil_heating coil;               ///< the coils' heat (off by default)
  /// The table's settling after each turn and when the coils are released before a dwell
  /// (turntable.hpp, schedule.hpp; off by default): docs/SIMULATOR.md §4, "Settling".
  settle_model settle;
  double release_before_dwell_s = -1.0;
  std::uint64_t seed = 1;
};

/// The ADC of a simulation: its part with the rig's filter word and chopping.
[[nodiscard]] ad7739_config adc_config(const simulation_config& c);

/// A chunk of conversions, column-wise. `angle_deg` is NaN while the table turns; `dwell` is
/// the global dwell index (0, 1, 2, ... alternating A, B, or the visiting order's positions) or
/// -1 outside acquisitions. The truth
/// columns (bias, g-term, Earth, input) are filled only when `truth` is set (the default);
/// without them a conversion costs ~7 % less (four columns fewer to write and average).
struct sample_block {
  explicit sample_block(std::size_t capacity, bool with_truth = true);
  std::size_t size = 0;
  bool truth = true;
  std::vector<double> time_s, angle_deg, rate_dps, temp_c;
  std::vector<double> bias_dps, g_term_dps, earth_dps, input_dps;
  std::vector<std::int64_t> dwell;
  [[nodiscard]] std::size_t capacity() const noexcept { return time_s.size(); }
};

class simulator {
 public:
  /// Errors: invalid sensor parameters, geometry, schedule, stepper, ADC or duration <= 0.
  [[nodiscard]] static result<simulator> make(const simulation_config& c);

  /// Fills `b` with the next conversions; returns how many (0 when the run is complete).
  std::size_t fill(sample_block& b) noexcept;

  [[nodiscard]] std::uint64_t total_samples() const noexcept { return total_; }
  [[nodiscard]] std::uint64_t produced() const noexcept { return k_; }
  [[nodiscard]] double conversion_time_s() const noexcept { return adc_.conversion_time_s(); }
  [[nodiscard]] const schedule& sched() const noexcept { return sched_; }
  [[nodiscard]] const simulation_config& config() const noexcept { return cfg_; }
  [[nodiscard]] const sensor::gyro& sensor_model() const noexcept { return gyro_; }
  [[nodiscard]] const ad7739& adc() const noexcept { return adc_; }
  /// Earth term and g-term (deg/s) seen at position A at temperature `temp_c`: their sum is
  /// the dN a calibration should find (paper eqn 11).
  [[nodiscard]] double earth_at_a_dps() const noexcept { return earth_[0]; }
  [[nodiscard]] double g_term_at_a_dps(double temp_c) const noexcept {
    return gf0_[0] + gf1_[0] * (temp_c - gyro_.temp_ref_c());
  }
  /// The rig's geometry (with its mount: azimuth, tilt).
  [[nodiscard]] const rig_geometry& geometry() const noexcept { return geo_; }
  /// Earth term and g-term (deg/s) the sensor sees at rest at table angle `angle_deg`, at
  /// temperature `temp_c` (its cross-axis sensitivity included; the truth of issue 33's terms).
  [[nodiscard]] double earth_at_dps(double angle_deg) const;
  [[nodiscard]] double g_term_at_dps(double angle_deg, double temp_c) const;

 private:
  simulator(const simulation_config& c, schedule s, sensor::gyro g, const ad7739& a,
            const rig_geometry& geo);
  void add_coil_heat(double* temp, std::size_t n) noexcept;
  // Conversions [first, first + n) of `b`, n <= chunk.
  void fill_chunk(sample_block& b, std::size_t first, std::size_t n) noexcept;
  // The rig terms of n conversions in consecutive cycle slots (from p_), into `b` from `first`
  // (their input rates at w_in_[scratch]); the truth columns too if `truth`.
  template <bool truth>
  void rig_run(sample_block& b, std::size_t first, std::size_t scratch, std::size_t n) noexcept;
  static constexpr std::size_t chunk = 512;  // conversions per pass through the stages
  simulation_config cfg_;
  schedule sched_;
  rig_geometry geo_;
  sensor::gyro gyro_;
  ad7739 adc_;
  double t_conv_s_, inv_sf_;
  std::uint64_t total_ = 0, k_ = 0;
  std::size_t p_ = 0;
  // Per cycle slot: sensed input gain, table rate, Earth rate, g-term parts, output angle, and
  // the dwell index as dwell_base + (dwell_mask & 2 cycle) (base -1 and mask 0 outside dwells).
  std::vector<double> in_gain_, table_, earth_, gf0_, gf1_, angle_out_;
  std::vector<std::int64_t> dwell_base_, dwell_mask_;
  double heat_dt_c_ = 0.0;  // the coils' temperature rise now
  // Per-chunk scratch: normal deviates, input rate, gyro output voltage, bias without truth.
  std::vector<double> n_arw_, n_adc_, w_in_, v_rel_, bias_;
};

/// One dwell average, as written to a recording (docs/FORMATS.md) plus its truth.
struct dwell_row {
  double time_s = 0.0, angle_deg = 0.0, rate_dps = 0.0, temp_c = 0.0;
  int n_avg = 0;
  double bias_dps = 0.0, g_term_dps = 0.0, earth_dps = 0.0, input_dps = 0.0;
};

/// Averages the acquisition conversions of each dwell (plain means of every column; the truth
/// means are NaN for blocks without truth).
class dwell_averager {
 public:
  explicit dwell_averager(int n_avg) : n_avg_(n_avg) {}
  /// Adds a block; complete dwells are appended to `out`. Runs of conversions with the same
  /// dwell index are summed column by column in one branch-free loop (the same sums, in the
  /// same order, as one conversion at a time).
  void add(const sample_block& b, std::vector<dwell_row>& out);

 private:
  void emit(std::vector<dwell_row>& out);
  template <bool truth>
  void accumulate(const sample_block& b, std::size_t first, std::size_t n) noexcept;
  int n_avg_;
  std::int64_t current_ = -1;
  int n_ = 0;
  double angle_ = 0.0;
  double sum_[8] = {};
};

}  // namespace gyroflip::rig
