/// \file
/// \brief One series' noise analysis (noise.hpp).
#include "gyroflip/analysis/noise.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/core/error.hpp"

namespace gyroflip::analysis {

status check_fit_range(const tau_range& range) {
  if (range.lo_s >= 0.0 && std::isfinite(range.lo_s) && range.hi_s > range.lo_s &&
      !std::isnan(range.hi_s))
    return ok();
  return parameter_error("fit_taus", fmt::format("the fitted taus run from lo to hi seconds with 0 "
                                                 "<= lo < hi; got lo {}, hi {}",
                                                 range.lo_s, range.hi_s));
}

namespace {

// Widens each resolved term of `main` by the fit-range systematic: the readings `alts` of the
// same data over other reasonable ranges. In the squared coefficient c: half the spread of the
// readings (main included) is added in quadrature to the standard error (z sd = hi^2 - c, as
// fit_noise_terms made the interval), and the interval is then widened to hold every reading.
void add_range_systematic(noise_terms& main, const std::vector<noise_terms>& alts) {
  const double z = std::sqrt(chi2_quantile(main.level, 1.0));
  const auto widen = [&](noise_term noise_terms::*member) {
    noise_term& t = main.*member;
    if (!t.resolved) return;
    double lo = t.value;
    double hi = lo;
    for (const auto& a : alts)
      if ((a.*member).resolved) {
        lo = std::min(lo, (a.*member).value);
        hi = std::max(hi, (a.*member).value);
      }
    t.range_lo = lo;
    t.range_hi = hi;
    const double c = t.value * t.value;
    const double z_sd = std::max(t.hi * t.hi - c, 0.0);
    const double half_spread = 0.5 * (hi * hi - lo * lo);
    const double z_total = std::hypot(z_sd, z * half_spread);
    t.lo = std::min(std::sqrt(std::max(c - z_total, 0.0)), lo);
    t.hi = std::max(std::sqrt(c + z_total), hi);
  };
  for (auto m : {&noise_terms::quantization, &noise_terms::arw, &noise_terms::bias_instability,
                 &noise_terms::rrw, &noise_terms::rate_ramp})
    widen(m);
  main.fit_ranges = 1 + alts.size();
}

}  // namespace

namespace {

// The fit of OADEV points `pts` (bounds at `level`) and what is read off them; `x` the phase for
// ADEV(1 s) when it is not among the points and for the long taus (null: a series with gaps,
// whose pooled points are all there is), `n_phase` and `tau0_s` the series'.
result<noise_analysis> fit_points(std::vector<deviation_point> pts, const phase_source* x,
                                  std::size_t n_phase, double tau0_s, double level,
                                  const tau_range& range, const noise_series& series,
                                  bool long_taus) {
  std::vector<deviation_point> fitted;
  for (const auto& p : pts)
    if (p.tau_s >= range.lo_s && p.tau_s <= range.hi_s) fitted.push_back(p);
  noise_analysis a;
  // A demodulator's correlated estimates (abba) have a known short-tau shape, which their ARW
  // basis models.
  if (range.detect_shaping && !series.shaped()) {
    a.shaping = detect_short_tau_shaping(fitted);
    fitted.erase(fitted.begin(), fitted.begin() + static_cast<std::ptrdiff_t>(a.shaping.points));
  }
  auto fit = fit_noise_terms(fitted, level, series);
  if (!fit) return fit.err();
  // The fit-range systematic: the same fit without the one or two shortest taus, and without
  // the longest (a few clusters), where at least 4 points remain.
  std::vector<noise_terms> alts;
  const auto n = fitted.size();
  for (const auto& [skip_lo, skip_hi] :
       {std::pair<std::size_t, std::size_t>{1, 0}, {2, 0}, {0, 1}, {1, 1}}) {
    if (n < skip_lo + skip_hi + 4) continue;
    const std::span<const deviation_point> sub(fitted.data() + skip_lo, n - skip_lo - skip_hi);
    if (auto f = fit_noise_terms(sub, level, series)) alts.push_back(std::move(*f));
  }
  add_range_systematic(*fit, alts);
  if (a.shaping.points > 0)
    fit->notes.push_back(fmt::format(
        "the {} shortest taus (to {:g} s) are left out of the fit: the curve there is shaped by "
        "{} (a concave kink, {:.1f} standard errors), which none of the five terms makes; "
        "--fit-taus LO:HI fits a range as given",
        a.shaping.points, a.shaping.kink_tau_s,
        a.shaping.cause == "line" ? "a spectral line (a sinusoid's bumps)"
                                  : "the sensor's low-pass (anti-alias) filter",
        a.shaping.kink_z));
  // ADEV(1 s): the datasheet's ARW reading, beside the fitted N.
  const double m1 = std::round(1.0 / tau0_s);
  if (m1 >= 1.0 && 2.0 * m1 < static_cast<double>(n_phase)) {
    const auto m = static_cast<std::size_t>(m1);
    const auto at =
        std::find_if(pts.begin(), pts.end(), [&](const deviation_point& p) { return p.m == m; });
    if (at != pts.end()) {
      a.adev_1s = at->dev;
    } else if (x == nullptr) {
      // not among the pooled points: left NaN
    } else if (auto one = deviation(dev_kind::oadev, *x, tau_spec{tau_spec::set::list, {m}});
               one && !one->empty()) {
      a.adev_1s = one->front().dev;
    }
    a.adev_1s_tau_s = m1 * tau0_s;
    const double t = a.adev_1s_tau_s;
    const auto sq = [](const noise_term& term) {
      return term.resolved ? term.value * term.value : 0.0;
    };
    const double others = 3.0 * sq(fit->quantization) / (t * t) +
                          2.0 * std::numbers::ln2 / std::numbers::pi * sq(fit->bias_instability) +
                          sq(fit->rrw) * t / 3.0 + sq(fit->rate_ramp) * t * t / 2.0;
    a.adev_1s_arw = std::sqrt(std::max(a.adev_1s * a.adev_1s - others, 0.0) * t);
  }
  if (long_taus && x != nullptr && !pts.empty() && x->size() >= 3) {
    std::vector<std::size_t> more;
    for (std::size_t m = 2 * pts.back().m; 2 * m + 1 <= x->size(); m *= 2) more.push_back(m);
    if (!more.empty()) {
      auto extra = deviation(dev_kind::oadev, *x, tau_spec{tau_spec::set::list, more});
      if (!extra) return extra.err();
      add_confidence(*extra, dev_kind::oadev, *x, level, {}, edf_rule::guarded);
      a.long_oadev = std::move(*extra);
    }
  }
  a.readoffs = read_off_terms(pts);
  a.oadev = std::move(pts);
  a.terms = std::move(*fit);
  return a;
}

}  // namespace

result<noise_analysis> analyse_noise(const phase_source& x, double level, const tau_range& range,
                                     const noise_series& series, const progress_fn& on_progress,
                                     bool long_taus) {
  if (auto s = check_confidence_level(level); !s) return s.err();
  if (auto s = check_fit_range(range); !s) return s.err();
  auto pts = deviation(dev_kind::oadev, x, {}, on_progress);
  if (!pts) return pts.err();
  // The OADEV points carry bounds at the same level as the terms. Their EDFs weight the fit, so
  // a noise type misread from a few points must not make one point outweigh the others: the
  // guarded rule (docs/ANALYSIS.md, "The guard").
  add_confidence(*pts, dev_kind::oadev, x, level, {}, edf_rule::guarded);
  return fit_points(std::move(*pts), &x, x.size(), x.tau0_s(), level, range, series, long_taus);
}

result<noise_analysis> analyse_noise(std::span<const phase_source* const> parts, double level,
                                     const tau_range& range, const noise_series& series) {
  if (auto s = check_confidence_level(level); !s) return s.err();
  if (auto s = check_fit_range(range); !s) return s.err();
  if (parts.empty()) return runtime_error("no part of the series to analyse");
  // Per octave factor m: the terms of every part that has any (GRADEV's sum over the terms whose
  // points all exist), n-weighted; the EDF the sum of the parts' (independent stretches).
  struct pooled {
    double sum_sq = 0.0;  // sum over the parts of n_k dev_k^2
    std::size_t n = 0;
    double edf = 0.0;
    std::size_t alpha_n = 0;
    int alpha = 0;
  };
  std::vector<std::pair<std::size_t, pooled>> by_m;
  std::size_t n_phase = 0;
  const double tau0_s = parts.front()->tau0_s();
  for (const phase_source* x : parts) n_phase = std::max(n_phase, x->size());
  // The octave factors of the longest part (OADEV's m <= (N-1)/4), each with every term of every
  // part that holds one (GRADEV's terms: none spans a gap).
  const auto factors = averaging_factors(tau_spec{}, dev_kind::oadev, n_phase);
  for (const phase_source* x : parts) {
    tau_spec here{tau_spec::set::list, {}};
    for (const std::size_t m : factors)
      if (x->size() >= 2 * m + 1) here.factors.push_back(m);
    if (here.factors.empty()) continue;  // too short a part for any factor
    auto pts = deviation(dev_kind::oadev, *x, here);
    if (!pts) continue;
    add_confidence(*pts, dev_kind::oadev, *x, level, {}, edf_rule::guarded);
    for (const auto& p : *pts) {
      if (p.n == 0) continue;
      auto it =
          std::find_if(by_m.begin(), by_m.end(), [&](const auto& e) { return e.first == p.m; });
      if (it == by_m.end()) {
        by_m.push_back({p.m, {}});
        it = std::prev(by_m.end());
      }
      pooled& q = it->second;
      q.sum_sq += static_cast<double>(p.n) * p.dev * p.dev;
      q.n += p.n;
      if (p.edf > 0.0) q.edf += p.edf;
      if (p.n > q.alpha_n) {  // the noise type of the part with the most terms
        q.alpha_n = p.n;
        q.alpha = p.alpha;
      }
    }
  }
  std::sort(by_m.begin(), by_m.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<deviation_point> pts;
  const double p_lo = 0.5 * (1.0 - level);
  for (const auto& [m, q] : by_m) {
    deviation_point p;
    p.m = m;
    p.tau_s = static_cast<double>(m) * tau0_s;
    p.n = q.n;
    p.dev = std::sqrt(q.sum_sq / static_cast<double>(q.n));
    p.alpha = q.alpha;
    p.edf = q.edf;
    if (p.edf > 0.0) {
      p.ci_lo = p.dev * std::sqrt(p.edf / chi2_quantile(1.0 - p_lo, p.edf));
      p.ci_hi = p.dev * std::sqrt(p.edf / chi2_quantile(p_lo, p.edf));
    } else {
      p.ci_lo = p.ci_hi = std::numeric_limits<double>::quiet_NaN();
    }
    pts.push_back(p);
  }
  if (pts.empty()) return runtime_error("no averaging time fits: every gap-free part is too short");
  return fit_points(std::move(pts), nullptr, n_phase, tau0_s, level, range, series, false);
}

}  // namespace gyroflip::analysis
