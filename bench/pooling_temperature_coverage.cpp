/// \file
/// \brief Coverage of the dN(T) figure's prediction band on the simulator (review of issue 31,
/// H3; docs/METHOD-NOTES.md "A run-to-run spread that depends on temperature"): campaigns of
/// stationary runs of one sensor at several temperatures, each run a new power-up (the preset's
/// turn-on spread of the g-term and of its temperature coefficient), pooled by
/// method::fit_delta_n_random_effects as `gyroflip calibrate` pools them; then one more run (a new
/// power-up) at the lowest, the middle and the highest temperature, and whether its dN lies in
/// the band delta_n_model::new_run_interval_at draws there. Beside it, the band of a constant
/// between-run variance (before the review): t x sqrt(stderr_at^2 + new_run_var_dps2).
///
/// Usage: pooling_temperature_coverage [--campaigns N] [--sensor NAME] [--duration S]
///        [--temps 4,12,20,28,36] [--seed S] [--constant-spread 1]
/// Prints the coverage at each test temperature with its binomial standard error, and how often
/// the band fell below the line's own interval (delta_n_model::interval_at). --constant-spread 1
/// draws no turn-on spread of the g-term's temperature coefficient: the spread is the same at
/// every temperature (a curvature estimate of 0 or below is then common; fifth review of issue
/// 31, F14).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/cycles.hpp"
#include "gyroflip/method/delta_n_model.hpp"
#include "gyroflip/rig/profiles.hpp"
#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/simulate.hpp"

using namespace gyroflip;

namespace {

struct measured {
  double delta_n_dps = NAN, stderr_dps = NAN;
};

measured run_at(const sensor::preset& p, double temp_c, double duration_s, std::uint64_t seed) {
  rig::simulation_config c;
  c.sensor = p.params;
  c.temperature = rig::profile::constant(temp_c);
  c.duration_s = duration_s;
  c.seed = seed;
  const auto sim = workflow::simulate_rows(c, false);
  if (!sim) return {};
  const position_table table = c.rig.table();
  const auto rec = workflow::recording_rows(sim->rows, table);
  const auto cy = method::cycles_of_rows(p.name, rec, method::pairing::abba, {}, table);
  if (!cy) return {};
  const auto cal = method::calibrate(cy->cycles);
  if (!cal) return {};
  return {cal->delta_n_dps, cal->stderr_correlated_dps};
}

}  // namespace

int main(int argc, char** argv) {
  int campaigns = 200;
  std::string name = "hz1-90-100a";
  double duration_s = 600.0;
  std::vector<double> temps{4, 12, 20, 28, 36};
  std::uint64_t seed = 5000;
  bool constant_spread = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--campaigns")
      campaigns = std::atoi(v.c_str());
    else if (a == "--sensor")
      name = v;
    else if (a == "--duration")
      duration_s = std::atof(v.c_str());
    else if (a == "--constant-spread")
      constant_spread = v == "1";
    else if (a == "--seed")
      seed = std::strtoull(v.c_str(), nullptr, 10);
    else if (a == "--temps") {
      temps.clear();
      for (std::size_t s = 0; s < v.size();) {
        const std::size_t e = std::min(v.find(',', s), v.size());
        temps.push_back(std::atof(v.substr(s, e - s).c_str()));
        s = e + 1;
      }
    } else {
      std::fprintf(stderr, "pooling_temperature_coverage: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const auto* found = sensor::find_builtin(name);
  if (found == nullptr) {
    std::fprintf(stderr, "pooling_temperature_coverage: no preset %s\n", name.c_str());
    return 2;
  }
  sensor::preset chosen = *found;
  if (constant_spread) chosen.params.g_sens_tc_turn_on_sigma_dps_per_g_c = 0.0;
  const auto* p = &chosen;
  double mean_c = 0.0;
  for (const double t : temps) mean_c += t / static_cast<double>(temps.size());
  const std::vector<double> tests{temps.front(), mean_c, temps.back()};
  std::vector<int> hit_new(3, 0), hit_const(3, 0);
  int n = 0, hetero = 0, below_line = 0;
  for (int c = 0; c < campaigns; ++c) {
    std::vector<method::delta_n_point> pts;
    for (const double t : temps) {
      const auto m = run_at(*p, t, duration_s, ++seed);
      pts.push_back({t, m.delta_n_dps, m.stderr_dps});
    }
    const auto model = method::fit_delta_n_random_effects(pts, 1);
    if (!model) continue;
    ++n;
    hetero += std::isfinite(model->tau2_centre_dps2);
    const double t1 = analysis::t_one_sigma(static_cast<double>(model->dof));
    for (std::size_t j = 0; j < 3; ++j) {
      const auto fresh = run_at(*p, tests[j], duration_s, ++seed);
      const double miss = std::abs(fresh.delta_n_dps - model->eval(tests[j]));
      const double se = model->stderr_at(tests[j]);
      hit_new[j] += miss <= model->new_run_interval_at(tests[j]);
      below_line += model->new_run_interval_at(tests[j]) < model->interval_at(tests[j]);
      hit_const[j] += miss <= t1 * std::sqrt(se * se + model->new_run_var_dps2);
    }
  }
  const auto cov = [&](int h) {
    const double q = h / static_cast<double>(n);
    return fmt::format("{:.3f} ± {:.3f}", q, std::sqrt(q * (1.0 - q) / n));
  };
  fmt::print("{}{}: {} campaigns of {} runs of {:g} s at {} degC ({} with tau^2(T) estimated)\n",
             name, constant_spread ? " (constant spread)" : "", n, temps.size(), duration_s,
             fmt::join(temps, ", "), hetero);
  fmt::print("T (degC)  band of new_run_interval_at  constant-tau^2 band (before)\n");
  for (std::size_t j = 0; j < 3; ++j)
    fmt::print("{:8.1f}  {:27}  {}\n", tests[j], cov(hit_new[j]), cov(hit_const[j]));
  fmt::print("band below the line's own interval: {} of {}\n", below_line, 3 * n);
  return 0;
}
