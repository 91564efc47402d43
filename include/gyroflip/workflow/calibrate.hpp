/// \file
/// \brief Multi-run calibration (module workflow): dN of each stationary recording (paper eqns
/// 8-11), the runs pooled, and a dN(T) model over their temperatures; one sensor at a time.
/// What `gyroflip calibrate`, `gyroflip report` and Python's `gyroflip.calibrate_runs` run.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
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

/// Calibrates each file (method::calibrate of its cycles), pools all cycles (the pooled
/// correlated error from the files' own: io::pooled_correlated_stderr) and fits the dN model of
/// several files (io::fit_runs_model). The sensor and rig come from the recordings' metadata:
/// two sensors are refused, a rig setting that differs between files and a sensor nobody named
/// are warned about. Progress: one part per file. Errors: no file, a file given twice (by any
/// name), a file name that JSON cannot carry, a bad recording (FILE:LINE:COL), too few cycles,
/// a chosen degree (parameter `degree`) without several files with temperatures.
[[nodiscard]] result<calibrate_result> calibrate_runs(const calibrate_request& request,
                                                      const progress_fn& on_progress = {});

}  // namespace gyroflip::workflow
