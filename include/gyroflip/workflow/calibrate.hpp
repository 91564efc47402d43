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
#include "gyroflip/method/types.hpp"

namespace gyroflip::workflow {

struct calibrate_request {
  std::vector<std::string> files;  ///< recordings (CSV or `.gfr`), each a stationary run
  method::pairing pairing = method::pairing::abba;
  double angle_tolerance_deg = 0.0;  ///< encoder angles this close to 0/180 read as them
  std::optional<io::calibration_geometry> geometry;  ///< to split dN into Earth and g terms
  /// Degree of the dN(T) polynomial; nullopt: io::fit_runs_model's rule (a line over a
  /// temperature span of 2 degC or more, else the runs' weighted mean).
  std::optional<std::size_t> degree;
};

struct calibrate_result {
  io::calibration_record record;      ///< what `calibrate -o` writes (io::to_json)
  std::vector<std::string> warnings;  ///< `FILE: what`, for the caller to show
};

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

/// Calibrates each file (method::calibrate of its cycles), pools all cycles (the pooled
/// correlated error from the files' own: io::pooled_correlated_stderr) and fits the dN model of
/// several files (io::fit_runs_model). The sensor and rig come from the recordings' metadata
/// (one_sensor: two sensors are refused, a rig setting or power-on time that differs between
/// files is warned about), and so is a sensor nobody named. Progress: one part per file. Errors: no
/// file, a file given twice (by any name), a file name that JSON cannot carry, a bad recording
/// (FILE:LINE:COL), too few cycles, a chosen degree (parameter `degree`) without several files with
/// temperatures.
[[nodiscard]] result<calibrate_result> calibrate_runs(const calibrate_request& request,
                                                      const progress_fn& on_progress = {});

}  // namespace gyroflip::workflow
