/// \file
/// \brief The report a lab sends (module workflow; docs/REPORT.md): recordings calibrated (or,
/// with a calibration, compensated), each analysed, the paper's figures and the Allan plot drawn,
/// and one page written with its PDF, figures and summary.json into a report folder
/// (report/folder.hpp). What `gyroflip report` and Python's `gyroflip.report` run.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/method/types.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace gyroflip::workflow {

struct report_request {
  std::vector<std::string> files;                    ///< recordings (CSV or `.gfr`)
  std::string output;                                ///< the report folder DIR
  std::optional<io::calibration_geometry> geometry;  ///< split dN into Earth and g terms
  std::string calibration;  ///< a calibration file: compensate the files (else calibrate them)
  std::string title;        ///< empty: a title naming the run
  method::pairing pairing = method::pairing::abba;
  /// The rate the runs were commanded to (a rate table), with a calibration: each run's error
  /// and scale-factor error against it. Non-zero, within the simulator's rate bound.
  std::optional<double> expected_rate_dps;
  std::string command;  ///< the command (or call) exactly as run, for the provenance
  /// What to do next, in the front end's words (the CLI: the exact `calibrate -o` and
  /// `compensate` commands for these files; Python: the calls); empty: not said. The
  /// conclusion of a calibration quotes it unless a run failed the stationarity test.
  std::string next_step;
  std::string made_by = "gyroflip report";  ///< who made the folder (its list's first line)
  /// How the front end has a run's g-term checked, for the warning about a run whose g-term was
  /// not checked (no sensor specification: method::stationarity::caveats), as
  /// calibrate_request::sensor_hint (the library names no CLI flag); empty: not said.
  std::string sensor_hint;
  /// The sensor whose specification the runs' g-term is checked against, and whose preset gives
  /// the budget's repeatability (as calibrate_request::sensor); nullopt: the recordings' built-in
  /// preset by name, if any. Without one a report's own runs are not vouched for.
  std::optional<sensor::preset> sensor;
};

struct report_result {
  std::string summary_json;           ///< DIR/summary.json's text
  std::size_t figures = 0;            ///< figures drawn (each as PNG, SVG and PDF)
  std::vector<std::string> warnings;  ///< `FILE: what`, for the caller to show
};

/// Makes the report folder request.output. The folder is checked before any work (report/
/// folder.hpp) and built aside, so a failure leaves it as it was. Errors: the folder's, the
/// readers', a calibration that cannot be read, gnuplot or the PDF makers missing (what to
/// install), a number that is not finite.
[[nodiscard]] result<report_result> make_report(const report_request& request,
                                                const progress_fn& on_progress = {});

}  // namespace gyroflip::workflow
