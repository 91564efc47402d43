/// \file
/// \brief Issue 33 item 3's goal measured: north finding on the simulator with known truth. Per
/// seed, two runs of a four-position sweep (0, 90, 180, 270 deg, vertical table axis), the rig's
/// base turned 180 deg between them (so the table tilt x g-sensitivity term is removed), each
/// half the time; the heading's error against the true azimuth, over the dead-time bound
/// sqrt(2) (N + 0.664 B sqrt(d)) / (W_E cos(lat) sqrt(T)), and the share of errors within the
/// reported 1 sigma. Present in every run: the preset's full error model (warm), a table tilt,
/// its g-sensitivity, a scale-factor error and the turns' dead time.
///
///   build/bench/heading_coverage PRESET HOURS [SEEDS=200] [TILT_MRAD=1] [SF_PPM=5000]
///     [N_AVG=auto] [MODE=two|one] [SEED_BASE=1000]
///
/// MODE one: one run of HOURS at one azimuth, the error against the apparent heading (the
/// heading the table's term shifts; what the truth file names apparent_heading_deg).
/// Figures: docs/PERFORMANCE.md, "North finding".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gyroflip/core/units.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/simulate.hpp"

namespace {

namespace gm = gyroflip::method;
namespace gr = gyroflip::rig;
namespace gw = gyroflip::workflow;

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "heading_coverage: %s\n", what.c_str());
  std::exit(1);
}

struct one_run {
  gm::harmonic_fit fit;
  gw::simulation_truth truth;
  double dead_per_dwell_s = 0.0;
  double dwell_s = 0.0;
};

one_run run(const gr::simulation_config& c) {
  auto sim = gr::simulator::make(c);
  if (!sim) die(sim.err().message);
  one_run out;
  out.dead_per_dwell_s = sim->sched().dead_time_per_dwell_s();
  out.dwell_s = c.rig.n_avg * sim->conversion_time_s();
  auto rows = gw::simulate_rows(c, false);
  if (!rows) die(rows.err().message);
  out.truth = rows->truth;
  const auto table = c.rig.table();
  const auto rec = gw::recording_rows(rows->rows, table);
  const auto dwells = gm::indexed_dwells(rec);
  auto fit = gm::fit_harmonics(dwells, table);
  if (!fit) die(fit.err().message);
  out.fit = *fit;
  return out;
}

double wrap180(double d) {
  return std::remainder(d, 360.0);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3)
    die("usage: heading_coverage PRESET HOURS [SEEDS] [TILT_MRAD] [SF_PPM] [N_AVG] [MODE]");
  const std::string preset_name = argv[1];
  const double hours = std::atof(argv[2]);
  const int seeds = argc > 3 ? std::atoi(argv[3]) : 200;
  const double tilt = argc > 4 ? std::atof(argv[4]) : 1.0;
  const double sf_ppm = argc > 5 ? std::atof(argv[5]) : 5000.0;
  const int n_avg_arg = argc > 6 ? std::atoi(argv[6]) : 0;
  const bool two = !(argc > 7 && std::string(argv[7]) == "one");
  const std::uint64_t seed_base = argc > 8 ? std::strtoull(argv[8], nullptr, 10) : 1000;
  auto preset = gyroflip::sensor::load_preset(preset_name);
  if (!preset) die(preset.err().message);
  const auto& p = preset->params;
  gr::simulation_config c;
  c.sensor = p;
  c.sensor.scale_factor_error_ppm = sf_ppm;
  c.table_axis = "up";
  c.rig.positions_deg = {0.0, 90.0, 180.0, 270.0};
  c.mount.tilt_mrad = tilt;
  c.mount.tilt_azimuth_deg = 60.0;  // the tilt's direction on the rig (turns with the base)
  c.power_on_before_s = 3600.0;     // warm: no warm-up transient
  c.temperature = gr::profile::constant(p.temp_ref_c);
  const double lat = c.lat_deg;
  const double run_s = hours * 3600.0 / (two ? 2.0 : 1.0);
  c.duration_s = run_s;
  // The dwell: the planner's closed form tau* = sqrt(d tau_c), tau_c = N^2 / (0.4413 B^2), d the
  // sweep's dead time per dwell (measured from the schedule at the default dwell first).
  const double n = p.arw_dps_rthz, b = p.bias_instability_dps;
  int n_avg = n_avg_arg;
  double d = 0.0;
  {
    auto sim = gr::simulator::make(c);
    if (!sim) die(sim.err().message);
    d = sim->sched().dead_time_per_dwell_s();
    const double tau_c = n * n / (0.4413 * b * b);
    if (n_avg == 0)
      n_avg = static_cast<int>(std::lround(std::sqrt(d * tau_c) / sim->conversion_time_s()));
  }
  c.rig.n_avg = n_avg;
  const double total_s = hours * 3600.0;
  const double bound = gm::heading_dead_time_limit_deg(n, b, d, lat, total_s);
  const double white = gm::heading_white_limit_deg(n, lat, total_s);
  std::vector<double> err, z;
  double dwell_s = 0.0;
  for (int s = 0; s < seeds; ++s) {
    const double az = std::fmod(37.0 + 137.50776 * s, 360.0);  // spread over the circle
    c.mount.azimuth_deg = az;
    c.seed = seed_base + 2 * static_cast<std::uint64_t>(s);
    const one_run r1 = run(c);
    dwell_s = r1.dwell_s;
    const auto& f1 = r1.fit;
    double est = 0.0, sig = 0.0, truth = 0.0;
    if (two) {
      c.mount.azimuth_deg = std::fmod(az + 180.0, 360.0);
      c.seed += 1;
      const one_run r2 = run(c);
      const auto& f2 = r2.fit;
      auto h = gm::heading_two_azimuths(
          {f1.value[1], f1.value[2]},
          {f1.covariance[4], f1.covariance[5], f1.covariance[7], f1.covariance[8]},
          {f2.value[1], f2.value[2]},
          {f2.covariance[4], f2.covariance[5], f2.covariance[7], f2.covariance[8]}, 180.0);
      if (!h) die(h.err().message);
      est = h->first.heading_deg;
      sig = h->first.sigma_deg;
      truth = r1.truth.sensed_heading_deg;
    } else {
      const auto h = gm::heading_of(f1.value[1], f1.value[2], f1.covariance[4], f1.covariance[8],
                                    f1.covariance[5]);
      est = h.heading_deg;
      sig = h.sigma_deg;
      truth = r1.truth.apparent_heading_deg;
    }
    const double e = wrap180(est - truth);
    err.push_back(e);
    z.push_back(e / sig);
    std::fprintf(stderr, "seed %d az %.1f err %.3f sigma %.3f\n", s, az, e, sig);
  }
  double ss = 0.0, mean = 0.0, sig_mean = 0.0;
  int covered = 0;
  for (std::size_t i = 0; i < err.size(); ++i) {
    ss += err[i] * err[i];
    mean += err[i];
    covered += std::abs(z[i]) <= 1.0 ? 1 : 0;
    sig_mean += err[i] / z[i];
  }
  const double k = static_cast<double>(err.size());
  const double rms = std::sqrt(ss / k);
  std::printf(
      "%s %.1f h %s, tilt %.2f mrad, sf %.0f ppm, dwell %.3f s (n_avg %d), dead %.3f s/dwell, "
      "%d seeds:\n  rms error %.3f deg (mean %.3f), white limit %.3f, dead-time bound %.3f, "
      "ratio to bound %.3f (+- %.3f), mean reported sigma %.3f, coverage %.1f %% (+- %.1f)\n",
      preset_name.c_str(), hours, two ? "two azimuths 180 deg apart" : "one azimuth", tilt, sf_ppm,
      dwell_s, n_avg, d, seeds, rms, mean / k, white, bound, rms / bound,
      rms / bound / std::sqrt(2.0 * k), sig_mean / k, 100.0 * covered / k,
      100.0 * std::sqrt(0.683 * 0.317 / k));
  return 0;
}
