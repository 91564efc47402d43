/// \file
/// \brief Issue 33: what the sweep's two back-to-back dwells at each end are worth. The sweep
/// 0, 1, ..., n-1, n-1, ..., 1, 0 (simulate's default for three or more positions) dwells twice
/// at each end with no turn between. Are they one dwell of twice the length, or two? The
/// first harmonic's error of a run (method::indexed_run_variance: exact for the IEEE 952 terms'
/// gap two-sample variance; docs/PLANNER.md, "More positions"), at the sweep's planned dwell, for
///   - separate: each end dwell a row of its own, the period's least squares as
///     `calibrate --pairing harmonic` and `heading` fit a dwell recording (the reference);
///   - merged in the period: the two end dwells at the period's middle as one row (2 tau) in
///     the same per-period least squares (unweighted, as method/harmonic.cpp's blocks);
///   - merged across periods: what a row-per-conversion recording (`simulate --raw`) gave before
///     the end dwells were split again: one 2-tau dwell at each end, so the visiting period is
///     0(2 tau), 1, ..., n-1 (2 tau), ..., 1 of 2n-2 dwells, none of them mirrored in time;
///   - there and back: the device's order 0, 1, ..., n-1, ..., 1 (a CONFIGURE table names no
///     angle twice in a row), a turn before every dwell, at its own planned dwell.
/// Printed: sigma over the separate sweep's, for white noise alone and for the preset's noise.
///
///   build/bench/npos_end_dwells [RUN_S=3600]
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "gyroflip/method/plan.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/plan.hpp"

namespace {

namespace gm = gyroflip::method;

// Solves the 4x4 system a x = b in place (Gaussian elimination with partial pivoting).
std::array<double, 4> solve4(std::array<double, 16> a, std::array<double, 4> b) {
  constexpr std::size_t n = 4;
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t p = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::abs(a[r * n + c]) > std::abs(a[p * n + c])) p = r;
    for (std::size_t k = 0; k < n; ++k) std::swap(a[c * n + k], a[p * n + k]);
    std::swap(b[c], b[p]);
    for (std::size_t r = c + 1; r < n; ++r) {
      const double f = a[r * n + c] / a[c * n + c];
      for (std::size_t k = c; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  std::array<double, 4> x{};
  for (std::size_t r = n; r-- > 0;) {
    double s = b[r];
    for (std::size_t k = r + 1; k < n; ++k) s -= a[r * n + k] * x[k];
    x[r] = s / a[r * n + r];
  }
  return x;
}

// The period `p` with the dwells of each group in `groups` (indices into its dwells, adjacent in
// time) merged into one row: its mean at the group's mid time; the unweighted least squares of
// [1, t, cos, sin] over the rows, each row's weight spread evenly over its dwells.
gm::indexed_period merged(gm::indexed_period p,
                          const std::vector<std::vector<std::size_t>>& groups) {
  struct row {
    double t, a;
    std::vector<std::size_t> dwells;
  };
  std::vector<row> rows;
  for (const auto& g : groups) {
    double t = 0.0;
    for (const auto k : g) t += p.start_s[k] + 0.5 * p.dwell_s;
    rows.push_back(
        {t / static_cast<double>(g.size()), p.visit_deg[g.front()] * std::numbers::pi / 180.0, g});
  }
  double t_mean = 0.0;
  for (const auto& r : rows) t_mean += r.t;
  t_mean /= static_cast<double>(rows.size());
  std::array<double, 16> xtx{};
  const auto x_of = [&](const row& r) {
    return std::array<double, 4>{1.0, (r.t - t_mean) / p.period_s, std::cos(r.a), std::sin(r.a)};
  };
  for (const auto& r : rows) {
    const auto x = x_of(r);
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j) xtx[i * 4 + j] += x[i] * x[j];
  }
  std::fill(p.weight_c.begin(), p.weight_c.end(), 0.0);
  std::fill(p.weight_s.begin(), p.weight_s.end(), 0.0);
  for (const auto& r : rows) {
    const auto w = solve4(xtx, x_of(r));
    for (const auto k : r.dwells) {
      p.weight_c[k] = w[2] / static_cast<double>(r.dwells.size());
      p.weight_s[k] = w[3] / static_cast<double>(r.dwells.size());
    }
  }
  return p;
}

double sigma(const gm::plan_noise& n, const gm::indexed_period& p, double run_s) {
  const auto periods = static_cast<std::size_t>(run_s / p.period_s);
  return std::sqrt(gm::indexed_run_variance(n, p, periods).mean_var());
}

gm::indexed_period period(const std::vector<double>& visits, double tau, double dead) {
  auto p = gm::indexed_period_of(visits, tau, dead);
  if (!p) {
    std::fprintf(stderr, "npos_end_dwells: %s\n", p.err().message.c_str());
    std::exit(1);
  }
  return *p;
}

}  // namespace

int main(int argc, char** argv) {
  const double run_s = argc > 1 ? std::atof(argv[1]) : 3600.0;
  const std::vector<double> angles{0, 90, 180, 270};
  const std::vector<double> sweep{0, 90, 180, 270, 270, 180, 90, 0};
  const std::vector<double> rotated{0, 0, 90, 180, 270, 270, 180, 90};  // a raw run's merged view
  const std::vector<double> back{0, 90, 180, 270, 180, 90};
  std::printf(
      "preset       d (s)  dwell (s)  noise  merged-in-period  merged-across  there-and-back"
      " (its dwell)\n");
  for (const char* name : {"adxrs150", "hz1-90-100a"}) {
    const auto* preset = gyroflip::sensor::find_builtin(name);
    const auto full = gyroflip::workflow::plan_noise_of(preset->params);
    gm::plan_noise white;
    white.arw_dps_rthz = full.arw_dps_rthz;
    for (const double d : {0.1, 0.4, 2.0}) {
      const auto plan = gm::plan_indexed(full, sweep, d, run_s);
      const auto plan_back = gm::plan_indexed(full, back, d, run_s);
      if (!plan || !plan_back) return 1;
      const double tau = plan->dwell_s;
      const std::array<const gm::plan_noise*, 2> noises{&white, &full};
      for (const auto* n : noises) {
        const auto sep = period(sweep, tau, d);
        const double ref = sigma(*n, sep, run_s);
        const auto in_period = merged(sep, {{0}, {1}, {2}, {3, 4}, {5}, {6}, {7}});
        const auto across = merged(period(rotated, tau, d), {{0, 1}, {2}, {3}, {4, 5}, {6}, {7}});
        const double tb_tau = n == &white ? tau : plan_back->dwell_s;
        std::printf("%-12s %5.1f  %9.3f  %-5s  %16.3f  %13.3f  %14.3f (%.3f)\n", name, d, tau,
                    n == &white ? "white" : "all", sigma(*n, in_period, run_s) / ref,
                    sigma(*n, across, run_s) / ref, sigma(*n, period(back, tb_tau, d), run_s) / ref,
                    tb_tau);
      }
    }
  }
  return 0;
}
