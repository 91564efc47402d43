/// \file
/// \brief Maps library errors to the documented exit codes.
#include <cstdio>
#include <string_view>
#include <utility>

#include "commands.hpp"

namespace gyroflip::app {

namespace {

// Library parameters (error::parameter) and the options that set them.
constexpr std::pair<std::string_view, std::string_view> option_of_parameter[] = {
    {"sample_rate_hz", "--rate"},
    {"dataset", "--dataset"},
    {"taus", "--taus"},
    {"duration_s", "--duration"},
    {"n_avg", "--n-avg"},
    {"n_temp", "--n-temp"},
    {"positions_deg", "--positions"},
    {"steps_per_rev", "--steps-per-rev"},
    {"max_rate_sps", "--step-rate"},
    {"start_rate_sps", "--start-rate"},
    {"accel_sps2", "--accel"},
    {"filter_word", "--filter-word"},
    {"degree", "--degree"},
    {"settle_s", "--settle"},
    {"seed", "--seed"},
    {"coil_heat", "--coil-heat"},
    {"lat_deg", "--latitude"},
    {"window_s", "--drift-window"},
    {"delta_n_dps", "--delta-n"},
    {"fit_taus", "--fit-taus"},
    {"level", "--ci"},
    {"gaps", "--gaps split or --gaps fill"},
    {"gaps_split", "--gaps split"},
    {"topic", "--rostopic"},
    {"delimiter", "--delimiter"},
    {"decimal", "--decimal"},
    {"angle_tolerance_deg", "--angle-tolerance"},
    {"column", "--column"},
    {"expected_rate_dps", "--expected-rate"},
    {"campaigns", "--campaigns"},
    {"sensors", "--sensor"},
    {"azimuth_deg", "--azimuth"},
    {"tilt_mrad", "--tilt-mrad"},
    {"tilt_azimuth_deg", "--tilt-azimuth"},
    {"base_turn_deg", "--base-turn"},
};

}  // namespace

void warn(std::string_view message) {
  std::fprintf(stderr, "gyroflip: warning: %.*s\n", static_cast<int>(message.size()),
               message.data());
}

void note(std::string_view message) {
  std::fprintf(stderr, "gyroflip: note: %.*s\n", static_cast<int>(message.size()), message.data());
}

int report(const error& e) {
  std::string_view option;
  for (const auto& [param, opt] : option_of_parameter)
    if (param == e.parameter) option = opt;
  if (option.empty()) {
    std::fprintf(stderr, "gyroflip: error: %s\n", e.message.c_str());
  } else {
    std::fprintf(stderr, "gyroflip: error: %s (option %.*s)\n", e.message.c_str(),
                 static_cast<int>(option.size()), option.data());
  }
  return e.code == errc::runtime ? 1 : 2;
}

}  // namespace gyroflip::app
