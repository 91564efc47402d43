/// \file
/// \brief Command-line parsing for all subcommands: the only translation unit that includes
/// CLI11 (a 5-s header). Parsing only fills option structs; work runs after parsing.
#include <functional>
#include <memory>

#include <CLI/CLI.hpp>

#include "cli.hpp"
#include "commands.hpp"

namespace gyroflip::app {
namespace {

using action = std::function<int()>;

// Binds options to a shared struct and, when the subcommand is chosen, selects its run_.
template <class Options, class Run>
std::shared_ptr<Options> bind(CLI::App* sub, action& chosen, Run run) {
  auto opts = std::make_shared<Options>();
  sub->callback([opts, &chosen, run] { chosen = [opts, run] { return run(*opts); }; });
  return opts;
}

void setup_earth(CLI::App& app, action& chosen) {
  auto* sub = app.add_subcommand("earth", "Earth-rate component along a sensitive axis (deg/s)");
  auto o = bind<earth_options>(sub, chosen, run_earth);
  sub->add_option("--latitude", o->lat_deg, "geodetic latitude (deg, north positive)")->required();
  sub->add_option("--axis", o->axis, "sensitive axis at 0 deg: north|east|down|up or N,E,D")
      ->capture_default_str();
  sub->add_flag("--json", o->json, "print one JSON object");
}

}  // namespace

int run_cli(int argc, char** argv) {
  CLI::App app{"gyroflip: bias-drift compensation of MEMS gyroscopes by 0/180 deg sign reversal"};
  app.name("gyroflip");
  app.set_version_flag("--version", "gyroflip " GYROFLIP_VERSION);
  app.require_subcommand(1);
  action chosen;
  setup_earth(app, chosen);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;  // help/version -> 0, any parse error -> 2 (not CLI11's 100+)
  }
  return chosen ? chosen() : 2;
}

}  // namespace gyroflip::app
