/// \file
/// \brief The figures people judge a gyro and the method by (issue 10), built from the
/// library's results as report::figure values (figure.hpp renders them):
/// the dwell values at 0 and 180 deg over time (the paper's Figs 3/5/7/9), the compensated
/// output with its mean and std (Figs 4/6/8/10), the bias estimate c(t) (which the paper does
/// not show), dN per run with mean +- std (Tab. 3/4 as a figure), dN against temperature with
/// the fitted dN(T), its interval and a new run's prediction band, and the Allan plot with
/// bounds, the fitted IEEE 952 lines and their read-off points.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/noise_fit.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/io/noise_report.hpp"
#include "gyroflip/method/compensation.hpp"
#include "gyroflip/method/flip_pair.hpp"
#include "gyroflip/method/types.hpp"
#include "gyroflip/report/figure.hpp"

namespace gyroflip::report {

/// Dwell means (deg/s) at the two positions of `pair` (0 deg and 180 deg; their angles from
/// `table`) against time (s): paper Figs 3, 5, 7, 9. A table of more positions: one series per
/// position (the pair's first, then the others in the table's order).
[[nodiscard]] figure dwell_figure(std::span<const method::dwell> dwells, const std::string& title,
                                  const method::flip_pair& pair = {},
                                  const position_table& table = position_table::pair_0_180());

/// The compensated rate per cycle against time, its mean and sample std in the caption: paper
/// Figs 4, 6, 8, 10 (eqn 12). Without `show_mean` (a calibration run compensated with its own
/// dN, whose mean is zero by construction) the caption gives the std alone.
[[nodiscard]] figure compensated_figure(std::span<const method::compensated_cycle> cycles,
                                        const method::compensation_summary& summary,
                                        const std::string& title, bool show_mean = true);

/// The bias estimate c = (y_0 + y_180)/2 per cycle against time: what the flip removes.
[[nodiscard]] figure bias_figure(std::span<const method::cycle> cycles, const std::string& title);

/// dN of each run (index 1..n) with its correlated standard error (runs are independent: not
/// joined), and the runs' mean with +- one sample std as a band: the paper's Tab. 3 and 4 as a
/// figure. Runs whose temperatures span method::min_model_span_c or more are said to be pooled
/// across that span in the caption.
[[nodiscard]] figure delta_n_runs_figure(std::span<const io::calibration_entry> runs,
                                         const std::string& title);

/// dN of each run against its mean temperature (bars: correlated standard error), the fitted
/// dN(T), its 68 % interval (delta_n_model::interval_at: holds the true line) and, when the
/// model estimates it, the 68 % prediction band of a new run (delta_n_model::new_run_interval_at:
/// holds a new power-up's run), each labelled with what it holds.
[[nodiscard]] figure delta_n_temperature_figure(std::span<const io::calibration_entry> runs,
                                                const method::delta_n_model& model,
                                                const std::string& title);

/// One curve of the Allan plot: its points (with bounds) and, when fitted, its noise terms.
struct allan_curve {
  std::string name;
  std::vector<analysis::deviation_point> points;
  std::optional<analysis::noise_terms> terms;
  /// Points beyond Stable32's m <= (N-1)/4, up to (N-1)/2 (noise --long-taus): drawn open, not
  /// joined, not fitted.
  std::vector<analysis::deviation_point> beyond = {};
};

/// Log-log deviation against tau with confidence bars for every curve; for the first curve with
/// terms, the fitted IEEE 952 lines (N/sqrt(tau), 0.664 B, K sqrt(tau/3), sqrt(3) Q/tau,
/// R tau/sqrt(2); resolved terms only) and the read-off points: N at tau = 1 s, B at the floor,
/// K at tau = 3 s, each marked "extrapolated" when its tau lies outside the curve's taus.
/// `unit` is the deviation's unit ("deg/s").
[[nodiscard]] figure allan_figure(std::span<const allan_curve> curves, const std::string& unit,
                                  const std::string& title);

/// The same for gyro curves in deg/s, drawn in the units gyro specifications and the report's
/// noise table use: the deviation in deg/h, N in deg/sqrt(h) (read at tau = 1 h, where the N
/// line equals N), B in deg/h (the floor 0.664 B), K in deg/h/sqrt(h) (read at tau = 3 h), so
/// that every number on the plot is the table's number (IEEE 952 Annex C; FACTS §7).
[[nodiscard]] figure gyro_allan_figure(std::span<const allan_curve> curves_dps,
                                       const std::string& title);

/// The deliverable figure of `gyroflip noise --plot` (issue 34 item 2): every curve (one per
/// axis, in deg/s) with its bounds, its fitted term lines and read-off marks, in `unit`: "deg/h"
/// (N in deg/sqrt(h) read at 1 h, K in deg/h/sqrt(h) at 3 h: gyro_allan_figure's), "deg/s" or
/// "rad/s" (N read at 1 s, K at 3 s); for accelerometer curves (given in m/s^2) "m/s^2", "mg"
/// or "ug" (VRW N read at 1 s, acceleration random walk K at 3 s); the key inside the frame;
/// points beyond Stable32's limit open, with the limit's tau in the caption. Error (usage) for
/// another unit.
[[nodiscard]] result<figure> noise_figure(std::span<const allan_curve> curves_dps,
                                          const std::string& unit, const std::string& title);

/// The Allan curve of one analysed column (its OADEV with bounds, its fitted terms, its long
/// taus) in the figure's base unit: deg/s for a gyro, m/s^2 for an accelerometer
/// (io::noise_report::quantity), as noise_figure takes it.
[[nodiscard]] allan_curve noise_curve(const io::noise_report& r);

}  // namespace gyroflip::report
