/// \file
/// \brief One series' noise analysis (noise.hpp).
#include "gyroflip/analysis/noise.hpp"

#include <cmath>
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

result<noise_analysis> analyse_noise(const phase_source& x, double level, const tau_range& range,
                                     const noise_series& series, const progress_fn& on_progress) {
  if (auto s = check_confidence_level(level); !s) return s.err();
  if (auto s = check_fit_range(range); !s) return s.err();
  auto pts = deviation(dev_kind::oadev, x, {}, on_progress);
  if (!pts) return pts.err();
  // The OADEV points carry bounds at the same level as the terms. Their EDFs weight the fit, so
  // a noise type misread from a few points must not make one point outweigh the others: the
  // guarded rule (docs/ANALYSIS.md, "The guard").
  add_confidence(*pts, dev_kind::oadev, x, level, {}, edf_rule::guarded);
  std::vector<deviation_point> fitted;
  for (const auto& p : *pts)
    if (p.tau_s >= range.lo_s && p.tau_s <= range.hi_s) fitted.push_back(p);
  auto fit = fit_noise_terms(fitted, level, series);
  if (!fit) return fit.err();
  noise_analysis a;
  a.readoffs = read_off_terms(*pts);
  a.oadev = std::move(*pts);
  a.terms = std::move(*fit);
  return a;
}

}  // namespace gyroflip::analysis
