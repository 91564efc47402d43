/// \file
/// \brief Simulate to a recording, with its truth (module workflow): the rig simulator
/// (rig/simulator.hpp) run to a recording file (docs/FORMATS.md) and its truth file, or to
/// dwell rows in memory; and the one formula of the dN a calibration of the simulated run should
/// find. What `gyroflip simulate`, `reproduce` and Python's `gyroflip.simulate` run.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/method/types.hpp"
#include "gyroflip/rig/simulator.hpp"

namespace gyroflip::workflow {

/// What a simulated run's calibration should find.
struct simulation_truth {
  double earth_dps = 0.0;   ///< Earth term at position A (paper eqn 9 for a north axis)
  double g_term_dps = 0.0;  ///< g-term at position A at the run's start temperature
  /// dN = Earth term + g-term at A (paper eqn 11), at the start temperature. The one place of
  /// this formula: the truth file, Python's delta_n_truth_dps and the reproduction use it.
  double delta_n_dps = 0.0;
  /// Issue 33's terms (an indexed run, north finding): each position's Earth term and g-term at
  /// the start temperature, and their first harmonic over the table angle,
  /// r(theta) = b + c1 cos(theta) + s1 sin(theta) (least squares over the table's positions;
  /// exact when the positions are equally spaced).
  bool indexed = false;  ///< more than two positions, another order, an azimuth or a tilt
  std::vector<double> position_deg, earth_at_dps, g_term_at_dps;
  double earth_c1_dps = 0.0, earth_s1_dps = 0.0, g_c1_dps = 0.0, g_s1_dps = 0.0;
  /// Every harmonic term over the whole turn of the table, for any table (set for every run, not
  /// only an indexed one): the mean, and the first ([0]) and second ([1]) harmonics' cos and sin
  /// coefficients of the Earth term and of the g-term (the Fourier transform over
  /// harmonic_truth_steps angles; c1/s1 above are [0]). The simulator's geometry makes the
  /// second harmonic 0 to rounding (docs/SIMULATOR.md).
  double earth_mean_dps = 0.0, g_mean_dps = 0.0;
  std::array<double, 2> earth_c_dps{}, earth_s_dps{}, g_c_dps{}, g_s_dps{};
  /// The term c_h (s_h) a harmonic fit estimates: Earth + g-term (h = 1 or 2).
  [[nodiscard]] double c_dps(std::size_t h) const {
    return earth_c_dps.at(h - 1) + g_c_dps.at(h - 1);
  }
  [[nodiscard]] double s_dps(std::size_t h) const {
    return earth_s_dps.at(h - 1) + g_s_dps.at(h - 1);
  }
  /// The azimuth (deg from north, clockwise) of the sensitive axis at table 0 (its horizontal
  /// part), of the axis the gyro senses (with its cross-axis sensitivity), and the heading a
  /// single run reads when the g-term's first harmonic (tilt x g-sensitivity) is taken for
  /// Earth rate (table axis up; NaN when the axis is not vertical).
  double heading_deg = 0.0, sensed_heading_deg = 0.0, apparent_heading_deg = 0.0;
  double earth_horizontal_dps = 0.0;  ///< W_E cos(lat)
};

/// The angles of the table's whole turn the truth's harmonics are taken over (simulation_truth).
inline constexpr int harmonic_truth_steps = 360;

/// The truth of simulator `sim` made from `c` (its temperature at t = 0).
[[nodiscard]] simulation_truth truth_of(const rig::simulator& sim, const rig::simulation_config& c);

/// A simulation written as a recording (and its truth).
struct recording_request {
  rig::simulation_config config;  ///< taken whole (the rig's settings are its business)
  bool raw = false;               ///< every conversion (angle empty while turning), else dwells
  std::string output = "-";       ///< the recording CSV (`-`: standard output)
  std::string truth;              ///< the truth CSV, or empty for none
  /// The maker's name: the files' first `# key: value` line is `MADE_BY: recording` (or
  /// `truth`).
  std::string made_by = "gyroflip";
  /// `# key: value` lines next (the front end's inputs, enough to make the file again); the
  /// simulator's own (conversion time, cycle, turn, scale factor, every sensor parameter) follow.
  std::vector<io::csv_metadata> metadata;
};

/// Runs the simulation into request.output (and request.truth): both written to temporaries,
/// every number checked finite, and committed together (io::commit_all), so a failure leaves
/// neither. Progress in conversions. Errors: the simulator's (bad sensor, schedule, duration),
/// a file that cannot be written, a number that is not finite.
[[nodiscard]] result<simulation_truth> simulate_recording(const recording_request& request,
                                                          const progress_fn& on_progress = {});

/// A simulation held in memory: one row per dwell, with the truth columns.
struct simulated_run {
  std::vector<rig::dwell_row> rows;
  simulation_truth truth;
};

/// Runs the simulation into dwell rows (truth columns only when `with_truth`, which costs ~7 %).
/// Errors: the simulator's; a number that is not finite.
[[nodiscard]] result<simulated_run> simulate_rows(const rig::simulation_config& config,
                                                  bool with_truth,
                                                  const progress_fn& on_progress = {});

/// A dwell row as a recording row at its position of `table` (rig::rig_config::table; found by
/// its angle, table_moving while the table turns).
[[nodiscard]] method::row recording_row(const rig::dwell_row& d, const position_table& table);
/// The dwell rows as recording rows (method::row).
[[nodiscard]] std::vector<method::row> recording_rows(const std::vector<rig::dwell_row>& rows,
                                                      const position_table& table);

}  // namespace gyroflip::workflow
