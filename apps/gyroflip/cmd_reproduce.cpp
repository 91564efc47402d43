/// \file
/// \brief `gyroflip reproduce`: the paper's experiment on the simulator (workflow/reproduce.hpp,
/// docs/REPRODUCE.md): options -> one workflow call -> the comparison printed.
#include <fmt/format.h>

#include "command_line.hpp"
#include "commands.hpp"
#include "finite_output.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/workflow/reproduce.hpp"
#include "progress_bar.hpp"

namespace gyroflip::app {

int run_reproduce(const reproduce_options& o) {
  workflow::reproduce_request req;
  req.quick = o.quick;
  req.seed = o.seed;
  req.campaigns = o.campaigns;
  req.output = o.output;
  for (const auto& s : o.sensors) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size())
      return report(parameter_error(
          "sensors",
          fmt::format("'{}': expected NAME=FILE.toml (NAME adxrs150 or hz1-90-100a)", s)));
    req.sensor_files.push_back({s.substr(0, eq), s.substr(eq + 1)});
  }
  req.command = shell_command(o.command_line);
  req.made_by = "gyroflip reproduce";
  progress bar("reproduce: simulated runs", 1000);
  auto res = workflow::reproduce(req, per_mille(bar));
  bar.finish();
  if (!res) return report(res.err());
  if (auto s = print_checked(res->text, "<stdout>"); !s) return report(s.err());
  return 0;
}

}  // namespace gyroflip::app
