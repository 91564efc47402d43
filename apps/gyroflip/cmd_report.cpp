/// \file
/// \brief `gyroflip report FILE... -o DIR`: the report a lab sends (workflow/report.hpp,
/// docs/REPORT.md): options -> one workflow call -> what was written.
#include <array>

#include <fmt/format.h>

#include "command_line.hpp"
#include "commands.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/workflow/report.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {

int run_report(const report_options& o) {
  const auto pairing = method::parse_pairing(o.pairing);
  if (!pairing) return report(usage_error("--pairing must be abba or simple"));
  auto geometry = geometry_option(o.lat_deg, o.axis);
  if (!geometry) return report(geometry.err());
  std::vector<std::string> inputs = o.files;
  if (!o.calibration.empty()) inputs.push_back(o.calibration);
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
