/// \file
/// \brief `gyroflip report FILE... -o DIR`: the report a lab sends (workflow/report.hpp,
/// docs/REPORT.md): options -> one workflow call -> what was written.
#include <array>

#include <fmt/format.h>

#include "command_line.hpp"
#include "commands.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/method/demodulator.hpp"
#include "gyroflip/workflow/report.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {

int run_report(const report_options& o) {
  const auto pairing = method::parse_pairing(o.pairing);
  if (!pairing)
    return report(usage_error("--pairing must be " + method::scheme_names_joined(" or ")));
  auto geometry = geometry_option(o.lat_deg, o.axis);
  if (!geometry) return report(geometry.err());
  std::vector<std::string> inputs = o.files;
  if (!o.calibration.empty()) inputs.push_back(o.calibration);
  if (!o.sensor.empty()) inputs.push_back(o.sensor);  // a TOML preset is an input too
  if (auto s = io::check_outputs(inputs, std::array{o.output}); !s) return report(s.err());
  workflow::report_request req;
  req.files = o.files;
  req.output = o.output;
  req.geometry = *geometry;
  req.calibration = o.calibration;
  req.title = o.title;
  req.pairing = *pairing;
  req.expected_rate_dps = o.expected_rate_dps;
  req.command = shell_command(o.command_line);
  req.made_by = "gyroflip report";
  req.sensor_hint =
      o.calibration.empty()
          ? "`report --sensor NAME|FILE.toml`"
          : "calibrate the runs with `gyroflip calibrate FILE... --sensor NAME|FILE.toml -o "
            "cal.json` and report them with `--calibration cal.json`";
  if (!o.sensor.empty()) {
    auto p = sensor::load_preset(o.sensor);
    if (!p) return report(p.err());
    req.sensor = std::move(*p);
  }
  if (o.calibration.empty()) {
    // The exact commands that turn these runs into a calibration and use it (issue 31).
    std::vector<std::string> cal{"gyroflip", "calibrate"};
    cal.insert(cal.end(), o.files.begin(), o.files.end());
    if (std::isfinite(o.lat_deg)) {
      cal.insert(cal.end(), {"--latitude", fmt::format("{}", o.lat_deg), "--axis", o.axis});
    }
    if (o.pairing != "abba") cal.insert(cal.end(), {"--pairing", o.pairing});
    if (!o.sensor.empty()) cal.insert(cal.end(), {"--sensor", o.sensor});
    cal.insert(cal.end(), {"-o", "cal.json"});
    req.next_step = fmt::format(
        "Next: {}, then gyroflip compensate RUN.csv --calibration cal.json.", shell_command(cal));
  }
  progress bar("report", 1000);
  auto res = workflow::make_report(req, per_mille(bar));
  bar.finish();
  if (!res) return report(res.err());
  for (const auto& w : res->warnings) warn(w);
  fmt::print(
      "{}: index.html, report.pdf, summary.json and {} figures (PNG, SVG, PDF with their gnuplot "
      "scripts in figures/)\n",
      o.output, res->figures);
  return 0;
}

}  // namespace gyroflip::app
