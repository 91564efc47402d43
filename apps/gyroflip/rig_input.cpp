/// \file
/// \brief `.gfr` rig recordings as input (rig_input.hpp).
#include "rig_input.hpp"

#include <fmt/format.h>

#include "commands.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/rigdata/rig_run.hpp"

namespace gyroflip::app {

bool is_rig_recording(const std::string& path) {
  return path.ends_with(".gfr");
}

result<io::recording_cycles> read_recording_cycles(const std::string& path, method::pairing p,
                                                   const progress_fn& on_progress,
                                                   double angle_tolerance_deg) {
  // A rig recording's positions come from the device's step count, not an encoder.
  if (!is_rig_recording(path)) return io::read_cycles(path, p, on_progress, angle_tolerance_deg);
  auto run = rigdata::read_rig_run(path);
  if (!run) return run.err();
  const auto rows = rigdata::dwell_rows(*run);
  auto rc = io::cycles_of_rows(path, rows, p, rigdata::csv_metadata(*run));
  if (!rc) return rc.err();
  rc->warnings = run->warnings;
  return rc;
}

result<io::series> read_rig_series(const std::string& path, const std::string& column) {
  auto run = rigdata::read_rig_run(path);
  if (!run) return run.err();
  // What the reader noticed (a damaged region skipped, a torn tail) is shown, not dropped.
  for (const auto& w : run->warnings) warn(w);
  const auto rows = rigdata::dwell_rows(*run);
  std::vector<double> values, time_s, angle_deg;
  if (column == "dwell_dps") {
    for (const auto& r : rows) {
      values.push_back(r.rate_dps);
      time_s.push_back(r.time_s);
      angle_deg.push_back(r.angle_deg);
    }
  } else if (column == "rate_dps" || column == "bias_dps") {
    auto rc = io::cycles_of_rows(path, rows, method::pairing::abba, {});
    if (!rc) return rc.err();
    for (const auto& c : rc->cycles) {
      values.push_back(column == "rate_dps" ? c.rate_dps : c.bias_dps);
      time_s.push_back(c.time_s);
    }
  } else {
    return about_parameter(
        input_error({path}, fmt::format("a rig recording has no series '{}': use rate_dps (per "
                                        "cycle, flip-compensated), bias_dps or dwell_dps",
                                        printable(column, 60))),
        "column");
  }
  return io::series_of_samples(path, std::move(values), time_s, std::move(angle_deg),
                               rigdata::csv_metadata(*run));
}

}  // namespace gyroflip::app
