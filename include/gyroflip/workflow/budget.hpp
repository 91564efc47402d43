/// \file
/// \brief The uncertainty budget of dN (module workflow; docs/REPORT.md, "The dN budget"): the
/// within-run (correlated) error, the run-to-run repeatability (from the runs, or the sensor
/// preset's turn-on spread when they cannot show it, labelled so), the error of the dN(T) model
/// (flagged when the fit has no degrees of freedom), and their combination for the calibrated
/// value and for the dN of a new power-up, which is what a compensated rate inherits.
#pragma once

#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/method/delta_n_model.hpp"
#include "gyroflip/method/stationarity.hpp"
#include "gyroflip/sensor/params.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::workflow {

struct delta_n_budget {
  std::size_t runs = 0;
  /// Within-run (correlated) error of the runs' dN pooled (method::pooled_correlated_stderr).
  double within_run_dps = 0.0;
  /// What one run like these gives on its own: the median of the runs' own correlated errors
  /// (within_run_dps is k runs pooled, about sqrt(k) smaller).
  double single_run_dps = 0.0;
  /// Repeatability of dN from one power-up to the next (one sample std); NaN when unknown.
  double run_to_run_dps = 0.0;
  bool run_to_run_measured = false;  ///< false: from the sensor preset, or unknown
  /// The runs' std about the model as measured (NaN without degrees of freedom); run_to_run_dps
  /// is this, or where it is below the runs' own noise (single_run_dps) that noise or the
  /// preset's turn-on spread, whichever is larger (run_to_run_floored).
  double runs_std_dps = std::numeric_limits<double>::quiet_NaN();
  bool run_to_run_floored = false;
  /// Degrees of freedom of a measured repeatability (runs less the model's coefficients): the
  /// std of 1 degree of freedom is uncertain by 1/sqrt(2) (~70 %) and is flagged.
  std::size_t run_to_run_dof = 0;
  std::string run_to_run_source;  ///< what it is and where it comes from
  /// Student's t at 68.3 % for the runs' degrees of freedom (1: not a random-effects fit, or no
  /// degrees of freedom): the calibrated value's and a new power-up's +- are 68.3 % intervals.
  double coverage_factor = 1.0;
  /// true for one run with the preset's spread sigma: the calibrated run and a new power-up are
  /// two draws of it, so dN moves by sqrt(2) sigma between them and new_power_up_dps holds
  /// sqrt(calibration^2 + 2 run_to_run^2) (fifth review of issue 31, F17).
  bool run_to_run_two_draws = false;
  /// The between-run std of dN the random-effects fit estimated (sqrt of its tau^2; NaN when
  /// not estimated). Below run_to_run_dps, which also holds the runs' own noise.
  double between_run_dps = std::numeric_limits<double>::quiet_NaN();
  /// The dN(T) (or weighted-mean) model's standard error at the runs' temperatures (largest);
  /// empty without a model or when it is not determined (model_note says why).
  std::optional<double> model_dps;
  std::string model_note;
  /// The error of the calibrated dN value (the model's, else the one run's within-run error,
  /// or, for a fit without degrees of freedom, within-run and repeatability combined).
  double calibration_dps = 0.0;
  /// A new power-up's dN about the calibrated value: sqrt(calibration^2 + (coverage_factor x
  /// run_to_run)^2), a 68.3 % interval. A rate
  /// compensated with this calibration carries it as a systematic error (paper eqn 12).
  double new_power_up_dps = 0.0;
  /// true: new_power_up_dps is the tau^2(T) band at the runs' temperatures (widest), not the
  /// combination above (new_power_up_at).
  bool new_power_up_from_band = false;
  /// The runs' own random-effects fit whose between-run variance changes with temperature
  /// (tau^2(T), with the fitted runs it is drawn from): the one fit every new_power_up_at takes
  /// its band from (compensate and report quote the same ± for a run; a model read from a file
  /// holds no fitted runs). Empty where the model given to budget_of estimates no tau^2(T).
  std::optional<method::delta_n_model> band_model;
  double temp_c = 0.0;  ///< the temperature the preset's spread is evaluated at
  /// A run compensated away from the calibration runs' temperatures (a constant dN): how far
  /// (degC beyond their span, 0 inside), the change of dN over that distance the sensor preset's
  /// temperature coefficients give (an assumption; add_temperature_term), and what it is.
  double outside_c = 0.0;
  double temperature_dps = 0.0;
  std::string temperature_note;
  /// false: outside the calibration's temperatures with no coefficient known, so no uncertainty
  /// covers the run (new_power_up_dps is then NaN and the page says "not valid").
  bool valid = true;
  /// Why there is no +- when !valid, as the page says it (outside the calibration's temperatures
  /// with no coefficient known, or a calibration that lists no runs and states no error).
  std::string invalid_why = "not valid outside the calibration's temperatures";
  /// What the within-run row is when it is not the runs' (a calibration that lists no runs:
  /// its own stated error); empty: the runs' own errors.
  std::string within_run_note;
};

/// Beyond this distance (degC) from the calibration runs' temperatures, a constant dN gets a
/// temperature term in its budget (the paper's HZ1 dN moves 7.2e-4 deg/s over 16 degC, Tab. 3:
/// 2 degC is about its runs' within-run error, docs/REPORT.md).
inline constexpr double outside_calibration_c = 2.0;

/// How much dN moves per degC by a sensor preset: its g-term's temperature coefficient along the
/// flipped axis (x 1 g) and that coefficient's spread from one power-up to the next, combined
/// (sensor/params.hpp g_sens_tc_z, g_sens_tc_turn_on_sigma); 0 when the preset states neither.
[[nodiscard]] double delta_n_tc_dps_per_c(const sensor::sensor_params& p) noexcept;

/// Adds the temperature term for a run `outside_c` degC beyond the calibration runs' span (named
/// `span`, as "4.0-20.0 degC") to `b`: delta_n_tc_dps_per_c x distance, combined with the new
/// power-up's error; without a coefficient (no preset, or one that states none) the budget is
/// marked not valid instead of printing a +- that does not cover the run.
void add_temperature_term(delta_n_budget& b, double outside_c, std::string_view span,
                          const sensor::sensor_params* preset, const std::string& preset_name);

/// The turn-on spread of dN a sensor model draws (sensor/params.hpp): the change of the g-term
/// along the axis the rig turns upside down (1 g) and of its temperature coefficient, at `temp_c`:
/// sqrt(s_g^2 + (s_tc (T - T_ref))^2) deg/s (docs/REPRODUCE.md, "The run-to-run spread").
[[nodiscard]] double turn_on_spread_dps(const sensor::sensor_params& p, double temp_c) noexcept;

/// The budget of dN from the runs' calibrations and their model (method::fit_runs_model; none for
/// one run); no runs: not valid (nothing to take an uncertainty from). `preset` gives the
/// repeatability when the runs cannot (one run, or a fit with no degrees of freedom); `preset_name`
/// names it in the labels.
[[nodiscard]] delta_n_budget budget_of(std::span<const io::calibration_entry> runs,
                                       const std::optional<method::delta_n_model>& model,
                                       const sensor::sensor_params* preset,
                                       const std::string& preset_name);

/// Whether the ΔN(T) line `applied` (a calibration file's) is `refit`, the fit of the runs the
/// file lists: the same t_ref_c and coefficients, each to 1e-9 relative. When not, the file was
/// edited by hand or made by other software, and its runs' statistics do not describe it.
[[nodiscard]] bool same_line(const method::delta_n_model& applied,
                             const method::delta_n_model& refit);

/// Runs whose dN disagree by a chi^2/dof beyond this about their fit were not made under the same
/// conditions: the paper's own runs scatter 14-30 times their errors (chi^2/dof 200-900).
inline constexpr double max_runs_chi2_per_dof = 1e4;

/// The warning `calibrate` and `report` give when the runs' fit (method::fit_runs_model) has a
/// chi^2/dof beyond max_runs_chi2_per_dof (fifth review of issue 31, F15: calibrate said nothing
/// where report warned); none otherwise.
[[nodiscard]] std::optional<std::string> runs_disagree_warning(
    const std::optional<method::delta_n_model>& runs_model);

/// Runs whose dN agree so much better than their own errors allow that chi^2 over their fit lies
/// this far in its lower tail (P(chi^2_dof <= x) below it) are the same data twice, not
/// independent power-ups (fifth review of issue 31, F9): for 2 dof, chi^2/dof below 1e-4.
inline constexpr double min_runs_chi2_lower_tail = 1e-4;

/// The warning `calibrate` and `report` give when the runs' fit has its chi^2 in that far lower
/// tail (analysis::chi2_cdf); none otherwise (and none for a fit without degrees of freedom).
[[nodiscard]] std::optional<std::string> runs_too_alike_warning(
    const std::optional<method::delta_n_model>& runs_model);

/// A new power-up's ΔN error at `temp_c` (deg/s, 68.3 %): where the budget's runs estimate a
/// between-run variance that changes with temperature (b.band_model: tau^2(T), the band the
/// ΔN(T) figure draws, delta_n_model::new_run_interval_at), that band at `temp_c`, with the
/// budget's temperature term; otherwise b.new_power_up_dps (third review of issue 31, M2: the
/// page quoted ±0.0029 where its figure drew ±0.0056 at 4 °C). NaN when the budget is not valid.
[[nodiscard]] double new_power_up_at(const delta_n_budget& b, double temp_c);

/// The g-sensitivity a sensor's specification states (sensor_params g_sens_spec_max/typ, with
/// their sources), as the stationarity test takes it; nullopt when the preset states neither.
[[nodiscard]] std::optional<method::g_term_spec> g_term_spec_of(const sensor::preset& p);

/// The same for a built-in preset's name; nullopt for another name (docs/FACTS.md §4-5).
[[nodiscard]] std::optional<method::g_term_spec> g_sensitivity_spec(const std::string& preset_name);

/// The scale-factor tolerance a sensor's specification states (a fraction: 0.02 is +-2 %) and its
/// source, for the presets whose datasheet gives one; nullopt otherwise (docs/FACTS.md §4).
struct scale_factor_spec {
  double fraction = 0.0;
  std::string source;
};
[[nodiscard]] std::optional<scale_factor_spec> scale_factor_tolerance(
    const std::string& preset_name);

/// `v` with the decimals that show its uncertainty `u` to two significant digits ("0.00327 ±
/// 0.00081", never "0.00326975 ± 0.000812"); without a usable u, 6 significant digits.
[[nodiscard]] std::string value_pm(double v, double u);

/// The same in degrees per hour, as the noise terms are quoted ("11.8 ± 2.9 °/h").
[[nodiscard]] std::string value_pm_dph(double v_dps, double u_dps);

/// What dN is, in plain words (paper eqns 7-12), for a calibration's page and its text.
[[nodiscard]] std::string delta_n_meaning();

/// When to calibrate again, from the budget: the power-up repeatability (measured or the
/// preset's) against the calibrated value's error, and the temperatures the runs covered
/// (`temps`, as "20.0 °C" or "4.0-20.0 °C"; empty: not known).
[[nodiscard]] std::string when_to_recalibrate(const delta_n_budget& b, const std::string& temps);

}  // namespace gyroflip::workflow
