/// \file
/// \brief The analysis of one run (analyse.hpp).
#include "gyroflip/workflow/analyse.hpp"

#include <algorithm>
#include <utility>

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/drift.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/method/demodulator.hpp"

namespace gyroflip::workflow {

namespace {

// The mean spacing of a series' stamps (s).
double mean_step(const std::vector<double>& t) {
  return t.size() > 1 ? (t.back() - t.front()) / static_cast<double>(t.size() - 1) : 1.0;
}

// OADEV with bounds and the IEEE 952 fit of `y` spaced `tau0_s` (a demodulator's estimates:
// `series` says its white-noise shape), or nothing when the series is too short for it (the report
// then shows what it has).
std::optional<analysis::noise_analysis> noise_of(const std::vector<double>& y, double tau0_s,
                                                 const analysis::noise_series& ns) {
  if (y.size() < 16 || !(tau0_s > 0.0)) return std::nullopt;
  const analysis::span_samples s(y);
  auto x = analysis::phase_source::make(s, analysis::input_kind::rate, tau0_s);
  if (!x) return std::nullopt;
  auto a = analysis::analyse_noise(*x, 0.683, {}, ns);
  if (a) return std::move(*a);
  // Too few points to fit: the curve alone.
  auto pts = analysis::deviation(analysis::dev_kind::oadev, *x, {});
  if (!pts) return std::nullopt;
  analysis::add_confidence(*pts, analysis::dev_kind::oadev, *x, 0.683);
  analysis::noise_analysis only;
  only.oadev = std::move(*pts);
  only.terms.chi2_per_dof = -1.0;  // marks "not fitted"
  return only;
}

// The median 0-deg dwell's data span (its conversions times their time) over the raw series'
// spacing, at most 1; 0 when the conversion time is unknown.
double raw_duty(const recording_run& run, double spacing_s) {
  std::vector<double> w;
  for (const auto& d : run.dwells)
    if (d.position == run.pair.plus) w.push_back(static_cast<double>(d.weight));
  if (w.empty() || !(run.conversion_s > 0.0) || !(spacing_s > 0.0)) return 0.0;
  return std::min(1.0, analysis::upper_median(std::move(w)) * run.conversion_s / spacing_s);
}

}  // namespace

bool noise_fitted(const analysis::noise_analysis& a) noexcept {
  return a.terms.chi2_per_dof >= 0.0;
}

std::optional<analysis::noise_terms> fitted_terms(const analysis::noise_analysis& a) {
  if (!noise_fitted(a)) return std::nullopt;
  return a.terms;
}

result<run_analysis> analyse_run(recording_run run, method::pairing p) {
  run_analysis a;
  a.pairing = p;
  auto cal = method::calibrate(run.cycles(p));
  if (!cal) return input_error({run.file}, cal.err().message);
  a.cal = *cal;
  // The pairing comparison: per-cycle statistics, and the OADEV at the longest common tau.
  std::vector<std::vector<analysis::deviation_point>> curves;
  double tau = 1e300;
  for (const auto q : {method::pairing::simple, method::pairing::abba}) {
    std::vector<double> y, stamps;
    for (const auto& c : run.cycles(q)) {
      y.push_back(c.rate_dps);
      stamps.push_back(c.time_s);
    }
    auto pts = analysis::deviation(analysis::dev_kind::oadev, y, analysis::input_kind::rate,
                                   mean_step(stamps), {});
    tau = std::min(tau, pts && !pts->empty() ? pts->back().tau_s : 0.0);
    curves.push_back(pts ? *pts : std::vector<analysis::deviation_point>{});
    auto c = method::calibrate(run.cycles(q));
    if (!c) continue;
    a.pairings.push_back({q, *c, std::nullopt});
  }
  for (std::size_t k = 0; k < a.pairings.size(); ++k) {
    const auto& curve = curves[a.pairings[k].pairing == method::pairing::abba ? 1 : 0];
    for (const auto& pt : curve)
      if (pt.tau_s <= tau * 1.5) a.pairings[k].oadev_at_common_tau = pt;
  }
  a.run = std::move(run);
  return a;
}

status compensate_run(run_analysis& a, const method::delta_n_model& model) {
  auto comp =
      compensate_cycles(a.run.cycles(a.pairing), model, method::drift_window_default_s, a.run.file);
  if (!comp) return comp.err();
  a.comp = std::move(*comp);
  std::vector<double> t, y, t0, y0;
  for (const auto& c : a.comp.cycles) {
    t.push_back(c.time_s);
    y.push_back(c.rate_dps);
  }
  // The raw sensor: its dwell means at 0 deg, one per cycle (what a fixed sensor would give).
  for (const auto& d : a.run.dwells)
    if (d.position == a.run.pair.plus) {
      t0.push_back(d.time_s);
      y0.push_back(d.rate_dps);
    }
  const double tc = mean_step(t);
  a.comp_noise = noise_of(y, tc, method::noise_series_of(a.pairing, tc));
  a.raw_noise = noise_of(y0, mean_step(t0), {});
  a.raw_duty = raw_duty(a.run, mean_step(t0));
  // The paper's own metric, raw beside compensated, at windows a reader can compare.
  a.drifts.clear();
  for (const double w : drift_windows_s) {
    const auto c = analysis::moving_mean_extremes(t, y, w);
    const auto r = analysis::moving_mean_extremes(t0, y0, w);
    if (!c || !r || w > 0.5 * a.comp.summary.duration_s) continue;
    a.drifts.push_back({w, r->range(), c->range()});
  }
  return ok();
}

}  // namespace gyroflip::workflow
