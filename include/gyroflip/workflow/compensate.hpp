/// \file
/// \brief Compensate and summarise (module workflow): paper eqn 12 per cycle, w_in = r - dN(T),
/// with the dN of a number or of a calibration (checked against the recording's sensor, rig and
/// temperature), and the summary every front end shows. The one compensate loop of `gyroflip
/// compensate`, `report`, `reproduce` and Python's `gyroflip.compensate`.
#pragma once

#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/method/compensation.hpp"
#include "gyroflip/method/cycles.hpp"
#include "gyroflip/method/delta_n_model.hpp"
#include "gyroflip/workflow/budget.hpp"

namespace gyroflip::workflow {

/// The dN a run is compensated with, and where it comes from.
struct delta_n_source {
  method::delta_n_model model;
  std::string source;  ///< the calibration's name, or empty for a number given as such
  std::optional<method::pairing> pairing;        ///< the pairing the calibration used
  std::optional<io::calibration_record> record;  ///< the calibration, when one was given
};

/// A constant dN given as a number. Errors: method::check_delta_n (parameter `delta_n_dps`).
[[nodiscard]] result<delta_n_source> delta_n_of_value(double delta_n_dps);
/// The dN of a calibration file (`calibrate -o`): its dN(T) model when it has one, else its
/// pooled dN. Errors: io::read_calibration_file.
[[nodiscard]] result<delta_n_source> delta_n_of_file(const std::string& path);
/// The same from the calibration's JSON text; `name` names it.
[[nodiscard]] result<delta_n_source> delta_n_of_json(std::string_view text,
                                                     const std::string& name);

/// Compensated cycles and their summary.
struct compensation {
  std::vector<method::compensated_cycle> cycles;
  method::compensation_summary summary;
  /// Cycles more than 1 degC outside the dN(T) model's fitted range (the model extrapolated).
  std::size_t outside_model = 0;
};

/// The one compensate loop: method::compensate (paper eqn 12) per cycle and
/// method::summarize over `drift_window_s`; every number checked finite (io::check_finite,
/// `what` names the output). Precondition: at least one cycle. Errors: drift window outside
/// (0, 1e9] s (parameter `window_s`), a number that is not finite.
/// "FILE: N of M cycles lie outside the dN(T) model's LO–HI °C: ΔN was extrapolated" (or
/// "all M cycles ...") for a compensation with outside_model > 0.
[[nodiscard]] std::string outside_model_warning(std::string_view file, const compensation& c,
                                                const method::delta_n_model& model);

[[nodiscard]] result<compensation> compensate_cycles(std::span<const method::cycle> cycles,
                                                     const method::delta_n_model& model,
                                                     double drift_window_s, std::string_view what);

/// `FILE: the same bytes as the calibration's run RUN (SHA-256) ...` for each run of `dn` whose
/// recorded SHA-256 is `sha256` (a run compensated with a calibration made of it is no
/// independent test of it; third review of issue 31, M5). Used by `compensate` and `report`.
[[nodiscard]] std::vector<std::string> same_run_warnings(const std::string& file,
                                                         const std::string& sha256,
                                                         const delta_n_source& dn);

/// The same for a recording in other bytes whose cycles are one of the calibration's runs': by
/// content where the calibration holds the run's print (method::find_in_print: 34 or more
/// consecutive dwells alike at one alignment, naming where; a copy rounded, shifted in time,
/// trimmed at either end, split or exported: fifth review of issue 31, F5), else by their count,
/// dN and std equal to the last digit (workflow::repeat_of's signature; a file without the run's
/// std: count and dN: a copy with one more newline, a `.gfr`'s CSV export, fourth review, F6).
/// `cycles` and their dwells' rates (method::recording_cycles::dwell_rates) as compensate read
/// them.
[[nodiscard]] std::vector<std::string> same_cycles_warnings(const std::string& file,
                                                            std::span<const method::cycle> cycles,
                                                            std::span<const double> dwell_rates,
                                                            const delta_n_source& dn);

/// The runs a calibration was made of, as `calibrate` tested them (schema 3).
struct calibration_runs_check {
  std::vector<std::string> failed;       ///< runs that failed the stationarity test
  std::vector<std::string> g_unchecked;  ///< runs that passed with their g-term not checked
  std::vector<std::string> untested;     ///< runs too short for the scatter and drift tests
  bool unchecked = false;                ///< some run has no test (a file written before it)
  std::vector<std::string> warnings;     ///< one per failed run, one for unchecked runs
};

/// Checks that a calibration's ΔN is the sensor's: every run it was made of passed the
/// stationarity test (method::check_stationarity, as recorded by `calibrate`). A run that failed
/// is a warning naming the calibration, the run and the statistic; with `strict` an input error
/// instead (a calibration of a turning table applied is w_in off by the table's rate). A ΔN
/// given as a number has no runs: nothing to check. A calibration that lists no runs is
/// `unchecked`, with no warning here: calibration_budget's says it, with its ±, in one sentence.
/// Used by `compensate`, `report` and Python (each with calibration_budget).
[[nodiscard]] result<calibration_runs_check> check_calibration_runs(const delta_n_source& dn,
                                                                    bool strict);

/// The uncertainty budget of a calibration file's ΔN, one reading for `compensate`, `report` and
/// Python (fifth review of issue 31, F3/F6: compensate applied a hand-edited ΔN, and quoted a
/// forged new-power-up error, that report flagged or recomputed). Its runs give it once the file's
/// ΔN is checked to be theirs (a model that is not their fit, a one-run ΔN not its run's, one
/// recording listed twice: a warning and `valid` false); without a specification the
/// repeatability is the one the file states, checked against its own parts (a new-power-up
/// error below the calibrated error or the repeatability: edited). A file that lists no runs
/// gets its own stated error as one run's, and one warning that nothing shows it was stationary
/// and what its ± is. `spec`: the sensor's specification, else
/// `named_preset` names it. Warnings (`FILE: what`) are appended.
[[nodiscard]] delta_n_budget calibration_budget(const delta_n_source& given,
                                                const sensor::preset* spec,
                                                const std::string& named_preset,
                                                std::vector<std::string>& warnings);

struct compensate_request {
  std::string file;  ///< the recording (CSV or `.gfr`)
  delta_n_source delta_n;
  std::optional<method::pairing> pairing;  ///< default: the calibration's, else abba
  double angle_tolerance_deg = 0.0;
  double drift_window_s = method::drift_window_default_s;
  /// Refuse a calibration made of a run that is not stationary, whose runs were not checked or
  /// are not listed, or whose ΔN or uncertainty is not what its runs give (edited); and a
  /// recording that is one of its runs (same bytes, or a copy by content: no independent test).
  bool strict = false;
};

/// A calibration of the harmonic scheme (named terms c1, s1[, c2, s2]) as compensate applies it
/// (issue 33; docs/METHOD-NOTES.md, "Compensating with harmonic terms"): the terms at each
/// position, T(theta) = c1 cos theta + s1 sin theta + c2 cos 2 theta + s2 sin 2 theta.
/// - Pairing `harmonic` (a run of 3 or more positions): T(theta) less its c1 part is subtracted
///   from every row at its position before the blocks are fitted, and the c1 of the calibration
///   (its dN(T)) from each block's c1: the rate along the sensitive axis at the table's 0 deg.
///   A term the run's table cannot separate (c2 at 0/120/240 deg aliases into c1) is so removed
///   before it can alias.
/// - A 0/180 pairing (abba, simple) of a pair at theta_+ and theta_+ + 180: dN is the half
///   difference (T(theta_+) - T(theta_+ + 180))/2 = c1 cos theta_+ + s1 sin theta_+ (the second
///   harmonic is the same at both and cancels), c1's dN(T) scaled by cos theta_+.
struct harmonic_application {
  std::vector<method::delta_n_term> terms;  ///< c1, s1[, c2, s2] of the calibration
  /// "at each position" or "at the pair's position A (90 deg): c1 cos + s1 sin"
  std::string how;
  /// The dN model subtracted from each cycle (pair: the half-difference's; harmonic: c1's).
  method::delta_n_model model;
  /// A 0/180 pairing: the pair's first position theta_+ (deg); NaN for the harmonic pairing.
  double pair_plus_deg = std::numeric_limits<double>::quiet_NaN();
};

/// The cycles of a recording read for a compensation with a harmonic calibration (`terms`:
/// harmonic_terms_of; `c1_model`: the calibration's dN model, c1's) and the application
/// (harmonic_application): the pairing asked for, else harmonic for 3 or more positions and abba
/// for two. One function for the CLI (compensate_file) and Python (rows in memory).
struct harmonic_cycles {
  method::recording_cycles cycles;
  harmonic_application applied;
  method::pairing pairing = method::pairing::harmonic;
};
[[nodiscard]] result<harmonic_cycles> read_harmonic_cycles(
    method::row_source& source, std::span<const method::delta_n_term> terms,
    const method::delta_n_model& c1_model, std::optional<method::pairing> asked,
    const progress_fn& on_progress = {});

/// The harmonic terms of a calibration (pairing harmonic, terms c1 and s1 at least); none for any
/// other calibration, whose one dN compensate subtracts as it is.
[[nodiscard]] std::optional<std::vector<method::delta_n_term>> harmonic_terms_of(
    const io::calibration_record& rec);

/// The dN model of a 0/180 pair at `plus_deg` from harmonic `terms` and c1's model `c1_model`:
/// c1(T) cos theta + s1 sin theta, its covariance propagated (c1's coefficients x cos^2; s1's
/// variance sin^2 on the constant). The errors compensate quotes are pair_errors_of's, which also
/// take the c1-s1 covariance and the run-to-run part.
[[nodiscard]] method::delta_n_model pair_model_of(const method::delta_n_model& c1_model,
                                                  std::span<const method::delta_n_term> terms,
                                                  double plus_deg);

/// The errors of the ΔN a compensation subtracted, at the run's mean temperature
/// (delta_n_errors_of).
struct delta_n_errors {
  /// The 68.3 % error of the ΔN subtracted, at the run's mean temperature (the calibration's own:
  /// delta_n_model::interval_at; a new power-up adds its repeatability): the same in every cycle,
  /// so no averaging reduces it (third review of issue 31, M5: only the within-run error was
  /// printed, 6.7 times smaller). NaN when the ΔN has no stated error (a number given as such).
  double delta_n_u_dps = std::numeric_limits<double>::quiet_NaN();
  /// What a rate compensated after a new power-up carries from the ΔN (68.3 %): the
  /// calibration's `uncertainty.new_power_up_dps`, what calibrate says to quote, or where its runs
  /// give a between-run variance that changes with temperature that band at the run's mean
  /// temperature (new_power_up_at; fourth review of issue 31, F2: compensate quoted the
  /// calibrated value's ±0.00013 where a new power-up's ΔN was off by 2.9 times that). NaN: not
  /// known (a file without `uncertainty`, a --delta-n) or not determined (delta_n_u_note).
  double new_power_up_dps = std::numeric_limits<double>::quiet_NaN();
  /// Why the ΔN's error is not known, when it is not (empty otherwise): "not determined (0
  /// degrees of freedom ...)", or a file from before calibrate wrote its uncertainty.
  std::string delta_n_u_note;
};

/// The errors of `dn` at the mean temperature of `cycles` (its reference temperature without
/// temperatures): the calibration's own and a new power-up's (see delta_n_errors), read from
/// `budget` (compensation_budget) for the dN `model` subtracted. A number given as such (no
/// calibration record) has neither, and says so in delta_n_u_note.
[[nodiscard]] delta_n_errors delta_n_errors_of(const delta_n_source& dn,
                                               std::span<const method::cycle> cycles,
                                               const delta_n_budget& budget,
                                               const method::delta_n_model& model);

/// The errors of the dN of a 0/180 pair at `plus_deg` made of a harmonic calibration `rec`,
/// from `c1` (delta_n_errors_of for the calibration's own model, c1's), by the delta method on
/// d = c1 cos theta + s1 sin theta with the terms' full covariance (rec.terms_covariance):
/// var d = k (cos^2 v11 + sin^2 v22 + 2 sin cos v12), k = u_c1^2 / v11 scaling the covariance
/// so that c1's variance is the one quoted for c1 (the budget's: its runs, Student's t); a new
/// power-up adds c1's run-to-run variance (new_power_up^2 - u_c1^2) whole at every angle: one
/// calibration does not measure s1's, and the turn-on change of a g-sensitivity vector in the
/// table's plane is taken as alike in both components. At theta_+ = 0 or 180 deg both equal c1's.
/// `c1` unchanged when the file has no covariance of c1 and s1.
[[nodiscard]] delta_n_errors pair_errors_of(const io::calibration_record& rec, double plus_deg,
                                            const delta_n_errors& c1);

/// The errors of the dN a compensation subtracted: delta_n_errors_of for the calibration's own
/// model, or for a harmonic calibration applied to a 0/180 pair, pair_errors_of (`applied`).
[[nodiscard]] delta_n_errors applied_errors_of(const delta_n_source& dn,
                                               std::span<const method::cycle> cycles,
                                               const delta_n_budget& budget,
                                               const harmonic_application* applied);

/// What `compensate --strict` (CLI and Python) takes: a calibration whose ΔN and uncertainty are
/// its runs' (`budget` valid), whose runs are listed and were checked for stationarity (not
/// `unchecked`, check_calibration_runs). An input error naming the calibration otherwise.
[[nodiscard]] status refuse_unvouched(const delta_n_source& dn, const delta_n_budget& budget,
                                      bool unchecked);

/// The budget of the calibration in `dn` (calibration_budget) with the sensor's specification
/// that the recording's `metadata` names (resolve_sensor_spec); an empty budget for a dN given as
/// a number. Warnings (`FILE: what`) are appended.
[[nodiscard]] delta_n_budget compensation_budget(const delta_n_source& dn,
                                                 std::span<const io::csv_metadata> metadata,
                                                 const std::string& file,
                                                 std::vector<std::string>& warnings);

struct compensate_result : delta_n_errors {
  compensation comp;
  /// A harmonic calibration applied (harmonic_application), else none.
  std::optional<harmonic_application> applied;
  method::pairing pairing = method::pairing::abba;
  std::vector<std::string> warnings;  ///< `FILE: what`, for the caller to show
};

/// A single-temperature dN applied more than this far from its calibration temperature is warned
/// about: the paper's HZ1-90-100A moved its dN by 7e-4 deg/s (23 %) between 20 and 4 degC
/// (docs/FACTS.md §3).
inline constexpr double far_from_calibration_c = 5.0;

/// Whether the calibration of `dn` (when it is one) fits a recording `file` with its metadata and
/// cycles: it must belong to the recording's sensor (refused otherwise); another rig setting, a
/// sensor unknown on one side, or a single-temperature dN applied more than
/// far_from_calibration_c from its temperature are warned about (appended to `warnings`).
[[nodiscard]] status check_calibration_fits(const std::string& file, const delta_n_source& dn,
                                            std::span<const io::csv_metadata> metadata,
                                            std::span<const method::cycle> cycles,
                                            std::vector<std::string>& warnings);

/// Reads the recording and compensates it. The calibration must belong to the recording's
/// sensor (refused otherwise), is warned about on another rig setting, more than
/// far_from_calibration_c from its temperature, a pairing other than its own, cycles outside
/// its dN(T) range. Errors: the reader's, a dN(T) model without temperatures in the recording,
/// compensate_cycles'.
[[nodiscard]] result<compensate_result> compensate_file(const compensate_request& request,
                                                        const progress_fn& on_progress = {});

/// The summary `compensate --json` prints and Python's compensate returns as "summary"
/// (schema gyroflip.compensate/2, docs/cli.md): file, delta_n (source, degree, coeffs_dps,
/// t_ref_c, delta_n_dps for a constant; its errors `error_dps` and `new_power_up_dps`, each null
/// when not known, with `error_note` saying why), pairing, cycles, duration_s, mean/std/stderr,
/// drift_dps (null when the run is shorter than the window), drift_window_s.
[[nodiscard]] nlohmann::json compensation_json(const compensation& c, const std::string& file,
                                               const delta_n_source& dn, method::pairing p,
                                               const delta_n_errors& errors);

}  // namespace gyroflip::workflow
