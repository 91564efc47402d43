/// \file
/// \brief Issue 33 item 2's goal measured: the N-position calibration's terms against their
/// Cramer-Rao bound on the simulator with known truth. Per seed one run of an N-position sweep
/// (horizontal table axis, the preset's full error model: white noise, bias instability, rate
/// random walk, the ADC's noise, a temperature ramp through the bias's temperature coefficient,
/// and the turns' dead time); the fit of every term the table separates
/// (method::fit_harmonics, options.separable) against the truth (the same fit of the run's true
/// Earth and g-terms, noise-free), its variance over the seeds against the bound
/// (method::harmonic_crlb: the model's restricted Fisher information for the preset's white,
/// flicker and random-walk noise, each visiting period's bias and slope as nuisance).
///
///   build/bench/npos_crlb PRESET MINUTES [SEEDS=200] [POSITIONS=0,72,144,216,288]
///     [RAMP_C=2] [N_AVG=0 (the preset's default)] [SEED_BASE=1]
///
/// RAMP_C: the temperature's rise over the run (degC, linear). Output: per term the variance
/// over the seeds, the bound, their ratio with its sampling error (sqrt(2/seeds)), and the mean
/// reported variance over the bound. Figures: docs/PERFORMANCE.md, "N-position indexing".
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gyroflip/core/text.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/noise_model.hpp"
#include "gyroflip/workflow/simulate.hpp"

namespace {

namespace gm = gyroflip::method;
namespace gr = gyroflip::rig;
namespace gw = gyroflip::workflow;

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "npos_crlb: %s\n", what.c_str());
  std::exit(1);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3)
    die("usage: npos_crlb PRESET MINUTES [SEEDS] [POSITIONS] [RAMP_C] [N_AVG] [SEED_BASE]");
  const std::string preset_name = argv[1];
  const double minutes = std::atof(argv[2]);
  const int seeds = argc > 3 ? std::atoi(argv[3]) : 200;
  const std::string positions = argc > 4 ? argv[4] : "0,72,144,216,288";
  const double ramp_c = argc > 5 ? std::atof(argv[5]) : 2.0;
  const int n_avg = argc > 6 ? std::atoi(argv[6]) : 0;
  const std::uint64_t seed_base = argc > 7 ? std::strtoull(argv[7], nullptr, 10) : 1;
  auto preset = gyroflip::sensor::load_preset(preset_name);
  if (!preset) die(preset.err().message);
  const auto& p = preset->params;
  gr::simulation_config c;
  c.sensor = p;
  c.sensor.scale_factor_error_ppm = 0.0;  // the terms as the truth states them
  const auto angles = gyroflip::text::to_doubles(positions, ',');
  if (!angles) die("POSITIONS: angles A,B,...");
  c.rig.positions_deg = *angles;
  if (n_avg > 0) c.rig.n_avg = n_avg;
  c.power_on_before_s = 3600.0;  // warm: the temperature ramp is the drift, not a warm-up
  c.duration_s = minutes * 60.0;
  const double t0 = p.temp_ref_c;
  auto temp =
      gr::profile::parse_temperature(fmt::format("ramp:{}:{}:{}", t0, t0 + ramp_c, c.duration_s));
  if (!temp) die(temp.err().message);
  c.temperature = *temp;
  const auto table = c.rig.table();
  gm::harmonic_options o;
  o.separable = true;
  std::vector<std::string> names;
  std::vector<double> bound, ideal, ss, reported;
  double dwell_s = 0.0, dead_s = 0.0, n_total = 0.0;
  std::size_t blocks = 0, period = 0;
  for (int s = 0; s < seeds; ++s) {
    c.seed = seed_base + static_cast<std::uint64_t>(s);
    auto rows = gw::simulate_rows(c, true);
    if (!rows) die(rows.err().message);
    const auto rec = gw::recording_rows(rows->rows, table);
    const auto dwells = gm::indexed_dwells(rec);
    const auto f = gm::fit_harmonics(dwells, table, o);
    if (!f) die(f.err().message);
    // The truth: the same fit of the noise-free Earth and g-terms of every row.
    auto truth_rows = rec;
    for (std::size_t k = 0; k < truth_rows.size(); ++k)
      truth_rows[k].rate_dps = rows->rows[k].earth_dps + rows->rows[k].g_term_dps;
    const auto tf = gm::fit_harmonics(gm::indexed_dwells(truth_rows), table, o);
    if (!tf) die(tf.err().message);
    const std::size_t m = f->names.size();
    if (s == 0) {
      names = f->names;
      ss.assign(m, 0.0);
      reported.assign(m, 0.0);
      auto sim = gr::simulator::make(c);
      if (!sim) die(sim.err().message);
      dwell_s = c.rig.n_avg * sim->conversion_time_s();
      dead_s = sim->sched().dead_time_per_dwell_s();
      n_total = gw::simulated_white_arw(*sim);
      // The simulator's noise exactly (its flicker as the Gauss-Markov bank it draws).
      const auto gap = gw::simulated_dwell_gap_avar(*sim, dwell_s);
      auto b = gm::harmonic_crlb(*f, dwells, table, gap);
      if (!b) die(b.err().message);
      bound = *b;
      // For comparison: the bound for the ideal flicker (IEEE 952's 1/f, method::gap_avar).
      gm::plan_noise noise;
      noise.arw_dps_rthz = n_total;
      noise.bias_instability_dps = p.bias_instability_dps;
      noise.rrw_dps_per_rts = p.rrw_dps_per_rts;
      auto bi = gm::harmonic_crlb(*f, dwells, table, noise, dwell_s);
      if (!bi) die(bi.err().message);
      ideal = *bi;
      blocks = f->blocks;
      period = f->period;
    }
    if (f->names != names) die("the terms changed between seeds");
    for (std::size_t i = 0; i < m; ++i) {
      const double e = f->value[i] - tf->value[i];
      ss[i] += e * e;
      reported[i] += f->var(i);
    }
  }
  const double k = seeds;
  std::printf(
      "%s, %.0f min, positions %s, ramp %.1f degC, dwell %.3f s, dead %.3f s/dwell, "
      "%zu periods of %zu dwells, white N %.4g (gyro %.4g + ADC), B %.3g, K %.3g, %d "
      "seeds:\n",
      preset_name.c_str(), minutes, positions.c_str(), ramp_c, dwell_s, dead_s, blocks, period,
      n_total, p.arw_dps_rthz, p.bias_instability_dps, p.rrw_dps_per_rts, seeds);
  const std::size_t m = names.size();
  for (std::size_t i = 1; i < m; ++i) {
    const double var = ss[i] / k, crlb = bound[(i - 1) * (m - 1) + (i - 1)];
    const double white_only = ideal[(i - 1) * (m - 1) + (i - 1)];
    std::printf(
        "  %-3s var %.4g  CRLB %.4g  ratio %.3f (+- %.3f)  reported/CRLB %.3f  "
        "(bound with ideal 1/f flicker %.4g: ratio %.3f)\n",
        names[i].c_str(), var, crlb, var / crlb, var / crlb * std::sqrt(2.0 / k),
        reported[i] / k / crlb, white_only, var / white_only);
  }
  return 0;
}
