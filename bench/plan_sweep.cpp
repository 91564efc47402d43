/// \file
/// \brief Issue 33 item 4's goal measured: on the simulator's sensor (the presets' full error
/// model, warm, at rest, 2-ms conversions), the realised error of a two-position run's
/// compensated rate at the planned dwell against a brute-force sweep of dwells and against the
/// planner's prediction, for both presets and dead times 0.1, 0.4 and 2 s. Common random numbers:
/// every dwell of the sweep carves the same seeds' records, so the sweep's comparisons are sharp.
///
///   build/bench/plan_sweep [SEEDS=400] [RUN_S=3600] [flip|heading]
///
/// `heading`: the same for an indexed run of four positions (0, 90, 180, 270 deg in the sweep
/// 0,1,2,3,3,2,1,0, a turn of the dead time between dwells at different angles): the realised
/// error is the RMS over the seeds of the first harmonic's components (c1, s1) that the
/// per-period least squares gives (method::indexed_period_of's weights), against
/// method::plan_indexed's dwell and prediction. The heading's error is this over W_E cos(lat),
/// so the ratios are the heading's.
///
/// One line per (preset, dead time, dwell); then per (preset, dead time) the planned dwell's
/// realised sigma over the sweep's best and over the prediction. Figures: docs/PERFORMANCE.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gyroflip/method/plan.hpp"
#include "gyroflip/sensor/gyro.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/plan.hpp"

namespace {

namespace gm = gyroflip::method;
namespace gs = gyroflip::sensor;

constexpr double dt = 0.002;  // one AD7739 conversion at FW 94 with chopping

// The sensor's rate output (deg/s) at rest for `run_s`, warm (on for an hour before).
std::vector<double> static_rates(const gs::sensor_params& p, double run_s, std::uint64_t seed) {
  auto g = gs::gyro::make(p, dt, 3600.0, seed);
  if (!g) {
    std::fprintf(stderr, "plan_sweep: %s\n", g.err().message.c_str());
    std::exit(1);
  }
  const auto n = static_cast<std::size_t>(run_s / dt);
  std::vector<double> y(n);
  for (std::size_t i = 0; i < n; ++i)
    y[i] = g->sample((static_cast<double>(i) + 0.5) * dt, p.temp_ref_c, 0.0).v_rel /
           p.scale_factor_v_per_dps;
  return y;
}

// The run's compensated rate: (mean of A dwells - mean of B dwells)/2 over whole pairs.
double run_estimate(const std::vector<long double>& prefix, double tau_s, double dead_s) {
  const auto m = static_cast<std::size_t>(std::lround(tau_s / dt));
  const std::size_t n = prefix.size() - 1;
  // Whole pairs only, as many as the planner counts (method::pairs_in).
  const std::size_t dwells = 2 * gm::pairs_in(static_cast<double>(n) * dt, tau_s, dead_s);
  long double sum = 0.0L;
  for (std::size_t k = 0; k < dwells; ++k) {
    const auto start =
        static_cast<std::size_t>(std::lround(static_cast<double>(k) * (tau_s + dead_s) / dt));
    const long double mean =
        (prefix[std::min(start + m, n)] - prefix[std::min(start, n)]) / static_cast<long double>(m);
    sum += (k % 2 ? -mean : mean);
  }
  return static_cast<double>(sum / static_cast<long double>(dwells));
}

// The indexed run's first harmonic (c1, s1) over whole periods; returns (c1^2 + s1^2) / 2.
double indexed_estimate(const std::vector<long double>& prefix, const gm::indexed_period& p,
                        std::size_t periods) {
  const auto m = static_cast<std::size_t>(std::lround(p.dwell_s / dt));
  const std::size_t n = prefix.size() - 1;
  long double c = 0.0L, s = 0.0L;
  for (std::size_t b = 0; b < periods; ++b)
    for (std::size_t k = 0; k < p.start_s.size(); ++k) {
      const auto start = static_cast<std::size_t>(
          std::lround((static_cast<double>(b) * p.period_s + p.start_s[k]) / dt));
      const long double mean = (prefix[std::min(start + m, n)] - prefix[std::min(start, n)]) /
                               static_cast<long double>(m);
      c += p.weight_c[k] * mean;
      s += p.weight_s[k] * mean;
    }
  const auto nb = static_cast<long double>(periods);
  return static_cast<double>((c * c + s * s) / (2.0L * nb * nb));
}

}  // namespace

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 400;
  const double run_s = argc > 2 ? std::atof(argv[2]) : 3600.0;
  const bool heading = argc > 3 && std::string(argv[3]) == "heading";
  const auto visits = gm::sweep_visits(std::vector<double>{0.0, 90.0, 180.0, 270.0});
  // The error (or its square's expectation) of a dwell tau at dead time d on the prefix sums.
  const auto period_of = [&](double tau, double d) {
    return *gm::indexed_period_of(visits, tau, d);
  };
  const auto periods_of = [&](const gm::indexed_period& p) {
    return static_cast<std::size_t>(std::floor(run_s / p.period_s));
  };
  const std::vector<double> deads{0.1, 0.4, 2.0};
  const std::vector<double> factors{0.3, 0.45, 0.6, 0.75, 0.9, 1.0, 1.15, 1.35, 1.6, 2.0, 2.6, 3.5};
  for (const auto* name : {"adxrs150", "hz1-90-100a"}) {
    const auto* preset = gs::find_builtin(name);
    const auto noise = gyroflip::workflow::plan_noise_of(preset->params);
    // Per dead time: the plan, and the sweep's dwells (the plan's times the factors, and 0.512 s).
    std::vector<gm::flip_plan> plans;
    std::vector<std::vector<double>> taus;
    for (const double d : deads) {
      plans.push_back(heading ? *gm::plan_indexed(noise, visits, d, run_s)
                              : *gm::plan_flip(noise, d, run_s));
      std::vector<double> t;
      for (const double f : factors) t.push_back(std::round(plans.back().dwell_s * f / dt) * dt);
      t.push_back(0.512);
      taus.push_back(t);
    }
    std::vector<std::vector<double>> sum2(deads.size(), std::vector<double>(factors.size() + 1));
    for (int s = 1; s <= seeds; ++s) {
      const auto y = static_rates(preset->params, run_s, static_cast<std::uint64_t>(s));
      std::vector<long double> prefix(y.size() + 1, 0.0L);
      for (std::size_t i = 0; i < y.size(); ++i) prefix[i + 1] = prefix[i] + y[i];
      for (std::size_t k = 0; k < deads.size(); ++k)
        for (std::size_t j = 0; j < taus[k].size(); ++j) {
          if (heading) {
            const auto p = period_of(taus[k][j], deads[k]);
            sum2[k][j] += indexed_estimate(prefix, p, periods_of(p));
          } else {
            const double e = run_estimate(prefix, taus[k][j], deads[k]);
            sum2[k][j] += e * e;
          }
        }
    }
    for (std::size_t k = 0; k < deads.size(); ++k) {
      const auto& p = plans[k];
      double best = INFINITY, best_tau = 0.0, planned = 0.0;
      for (std::size_t j = 0; j < taus[k].size(); ++j) {
        const double real = std::sqrt(sum2[k][j] / seeds);
        const auto ip = period_of(taus[k][j], deads[k]);
        const double pred =
            heading ? std::sqrt(gm::indexed_run_variance(noise, ip, periods_of(ip)).mean_var())
                    : std::sqrt(gm::flip_mean_variance(noise, taus[k][j], deads[k],
                                                       gm::pairs_in(run_s, taus[k][j], deads[k])));
        std::printf("%-12s d %.1f s  dwell %7.3f s  realised %.4g  predicted %.4g  ratio %.3f%s\n",
                    name, deads[k], taus[k][j], real, pred, real / pred,
                    j == factors.size() ? "  (paper)"
                    : factors[j] == 1.0 ? "  (plan)"
                                        : "");
        if (real < best) best = real, best_tau = taus[k][j];
        if (j < factors.size() && factors[j] == 1.0) planned = real;
      }
      // The sweep's minimum read from a parabola in (ln tau, sigma^2) through the lowest point
      // and its neighbours: less noisy than the lowest point itself, which is the minimum of a
      // dozen noisy values and so biased low by about a standard error.
      std::size_t lo = 0;
      for (std::size_t j = 1; j < factors.size(); ++j)
        if (sum2[k][j] < sum2[k][lo]) lo = j;
      lo = std::clamp<std::size_t>(lo, 1, factors.size() - 2);
      const double x0 = std::log(taus[k][lo - 1]), x1 = std::log(taus[k][lo]),
                   x2 = std::log(taus[k][lo + 1]);
      const double y0 = sum2[k][lo - 1] / seeds, y1 = sum2[k][lo] / seeds,
                   y2 = sum2[k][lo + 1] / seeds;
      const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
      const double a = (d12 - d01) / (x2 - x0), b = d01 - a * (x0 + x1);
      const double xm = a > 0 ? std::clamp(-b / (2 * a), x0, x2) : x1;
      const double fitted = std::sqrt(y0 + (xm - x0) * (d01 + a * (xm - x1)));
      std::printf("%-12s d %.1f s  parabola minimum %.4g at %.3f s: planned %.3f x it\n", name,
                  deads[k], fitted, std::exp(xm), planned / fitted);
      const double paper = std::sqrt(sum2[k].back() / seeds);
      std::printf(
          "%-12s d %.1f s  SUMMARY planned dwell %.3f s: realised %.4g = %.3f x the sweep's best "
          "(%.3f s), %.3f x the prediction %.4g; the paper's 0.512 s: %.3f x the plan's\n",
          name, deads[k], p.dwell_s, planned, planned / best, best_tau, planned / p.sigma_dps,
          p.sigma_dps, paper / planned);
    }
  }
  return 0;
}
