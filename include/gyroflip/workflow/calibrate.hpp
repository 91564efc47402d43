/// \file
/// \brief Multi-run calibration (module workflow): dN of each stationary recording (paper eqns
/// 8-11), the runs pooled, and a dN(T) model over their temperatures; one sensor at a time.
/// What `gyroflip calibrate`, `gyroflip report` and Python's `gyroflip.calibrate_runs` run.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/method/stationarity.hpp"
#include "gyroflip/method/types.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/budget.hpp"

namespace gyroflip::workflow {

struct calibrate_request {
  std::vector<std::string> files;  ///< recordings (CSV or `.gfr`), each a stationary run
  method::pairing pairing = method::pairing::abba;
  double angle_tolerance_deg = 0.0;  ///< encoder angles this close to 0/180 read as them
  std::optional<io::calibration_geometry> geometry;  ///< to split dN into Earth and g terms
  /// Degree of the dN(T) polynomial; nullopt: method::fit_runs_model's rule (a line over a
  /// temperature span of 2 degC or more, else the runs' weighted mean).
  std::optional<std::size_t> degree;
  /// The sensor whose specification the stationarity test's g-term is checked against
  /// (`calibrate --sensor NAME|FILE.toml`); nullopt: the recordings' built-in preset by name
  /// (`# sensor_name:`), if any.
  std::optional<sensor::preset> sensor;
  /// Refuse a run that fails the stationarity test (bad input, naming the run and the statistic)
  /// instead of warning (`calibrate --strict`).
  bool strict = false;
  /// How the front end names a sensor specification, for the warning about an unchecked g-term
  /// (the library names no CLI flag): "calibrate --sensor NAME|FILE.toml", "sensor=".
  std::string sensor_hint;
};

struct calibrate_result {
  io::calibration_record record;      ///< what `calibrate -o` writes (io::to_json)
  std::vector<std::string> warnings;  ///< `FILE: what`, for the caller to show
  /// What a user should quote (the same numbers `report` puts in its budget): the calibrated
  /// value's error, the repeatability, a new power-up's error.
  delta_n_budget budget;
};

/// The one resolver of the sensor specification a run is judged against (fourth review of issue
/// 31, F4/F7; what calibrate, report and Python's calibrate_runs and report use): the preset
/// `given` (`--sensor NAME|FILE.toml`, `sensor=`), else the sensor model a simulated recording
/// states in its `# sensor.KEY:` header (a TOML preset's), else the built-in preset named by its
/// `# sensor_name:`; nullopt when none. A `given` preset whose name is not the recording's
/// sensor_name (both known) is a warning naming both (`FILE: recorded with sensor 'A', but the
/// specification given is of 'B'`), and with `strict` an input error.
[[nodiscard]] result<std::optional<sensor::preset>> resolve_sensor_spec(
    const std::optional<sensor::preset>& given, std::span<const io::csv_metadata> metadata,
    const std::string& file, bool strict, std::vector<std::string>& warnings);

/// The geometry given (--latitude/--axis) against the recording's own `# latitude_deg:` and
/// `# axis:` header (fifth review of issue 31, F18: a contradiction split dN into Earth and g
/// wrongly, without a word): a warning naming both values, with `strict` an input error. Nothing
/// to check without a geometry or without the header lines.
[[nodiscard]] status check_geometry_header(const std::optional<io::calibration_geometry>& given,
                                           std::span<const io::csv_metadata> metadata,
                                           const std::string& file, bool strict,
                                           std::vector<std::string>& warnings);

/// The stationarity test's inputs for a run: the pairing, the specification of `preset` (none:
/// the g-term is not checked) and the geometry (none: a lower bound of the g-term).
[[nodiscard]] method::stationarity_inputs stationarity_inputs_of(
    method::pairing p, const sensor::preset* preset,
    const std::optional<io::calibration_geometry>& geometry);

/// The warning (or, `strict`, the error) for a run that failed the test: `FILE: not a stationary
/// run, so its mean r is not the sensor's dN: <the failed statistics>`.
[[nodiscard]] std::string stationarity_warning(const std::string& file,
                                               const method::stationarity& st);

/// How a calibration run's stationarity test stands: vouched for (every statistic passed, the
/// g-term included), failed, passed with its g-term unchecked (no specification: a constant input
/// of any size passes, method::stationarity::caveats), or untested (too few cycles).
enum class run_standing { vouched, failed, g_unchecked, untested };

/// Who is judged, for the messages: the run `file`, either itself (`within` empty: `FILE: ...`)
/// or as a run named in the calibration file `within` (`CAL: its run FILE: ...`); `task` is what
/// a strict refusal names ("calibration", "compensation", "report"); `hint` how the front end
/// names a specification, appended to the g-term caveat (the library names no CLI flag).
struct run_subject {
  std::string file;
  std::string within;
  std::string task = "calibration";
  std::string hint;
};

/// The one verdict on a calibration run that calibrate, compensate and report give (CLI and
/// Python; third review of issue 31, H1): a failed run is a warning (stationarity_warning), and
/// so is a run whose g-term was not checked; with `strict` either is an input error naming the
/// file (`within`, else `file`) and ending "refused (strict)", so that nothing strict rests on a
/// run the test does not vouch for. Returns the run's standing.
[[nodiscard]] result<run_standing> judge_run(const run_subject& who, const method::stationarity& st,
                                             bool strict, std::vector<std::string>& warnings);

/// The one-sensor check of several recordings, file by file (what calibrate_runs and
/// make_report both run): each recording's sensor and rig from its metadata (io::sensor_of);
/// a second sensor is refused (`FILE: recorded with sensor ..., but FIRST with ...: <task> one
/// sensor at a time`), a rig setting that differs from the first file's is a warning
/// (`FILE: rig setting differs from FIRST: n_avg 256 vs 128`), and so is another time the sensor
/// was on before the run (`power_on_before_s`, which moves a warm-up transient into dN).
class one_sensor {
 public:
  /// `task` names what is done one sensor at a time ("calibrate", "report on").
  explicit one_sensor(std::string task) : task_(std::move(task)) {}
  /// Adds the next file; its warnings are appended to `warnings`.
  [[nodiscard]] status add(const std::string& file, std::span<const io::csv_metadata> metadata,
                           std::vector<std::string>& warnings);
  /// The first file's sensor record (nullopt before the first add).
  [[nodiscard]] const std::optional<io::sensor_record>& sensor() const noexcept { return sensor_; }

 private:
  std::string task_, first_file_, first_power_on_;
  std::optional<io::sensor_record> sensor_;
};

/// The harmonic scheme's named terms of a calibration (issue 33 item 2) from each run's fit
/// (method::fit_harmonics with `separable`, one table and one set of terms): their plain mean with
/// the covariance of a mean of independent runs (the sum of the runs' covariances / k^2), in
/// `rec.terms` and `rec.terms_covariance`, and the separability report of `table` about the axis
/// `axis_text` names (a `# table_axis:` value; empty: not recorded, taken as horizontal) in
/// `rec.separability`. What calibrate_runs and Python's calibrate (arrays) run.
void add_harmonic_terms(std::span<const method::harmonic_fit> fits, const position_table& table,
                        const std::string& axis_text, io::calibration_record& rec);

/// Calibrates each file (method::calibrate of its cycles) and tests that it was stationary
/// (method::check_stationarity: a failing run is a warning, or with `strict` an error), pools all
/// cycles (the pooled
/// correlated error from the files' own: method::pooled_correlated_stderr) and fits the dN model of
/// several files (method::fit_runs_model). The sensor and rig come from the recordings' metadata
/// (one_sensor: two sensors are refused, a rig setting or power-on time that differs between
/// files is warned about), and so is a sensor nobody named. Progress: one part per file. Errors: no
/// file, a file given twice (by any name), a file name that JSON cannot carry, a bad recording
/// (FILE:LINE:COL), too few cycles, a chosen degree (parameter `degree`) without several files with
/// temperatures.
[[nodiscard]] result<calibrate_result> calibrate_runs(const calibrate_request& request,
                                                      const progress_fn& on_progress = {});

}  // namespace gyroflip::workflow
