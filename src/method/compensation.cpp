/// \file
/// \brief Paper eqn 12 and the summary of a compensated series (see compensation.hpp).
#include "gyroflip/method/compensation.hpp"

#include <cassert>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "gyroflip/analysis/drift.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/method/calibration.hpp"

namespace gyroflip::method {

status check_delta_n(double delta_n_dps) {
  if (std::abs(delta_n_dps) <= max_input_magnitude) return ok();
  return parameter_error("delta_n_dps",
                         fmt::format("dN must be a finite number of deg/s within +-{:g}; got {}",
                                     max_input_magnitude, delta_n_dps));
}

status check_drift_window(double window_s) {
  if (window_s > 0.0 && window_s <= drift_window_max_s) return ok();
  return parameter_error("window_s", fmt::format("the drift window must be in (0, {:g}] s; got {}",
                                                 drift_window_max_s, window_s));
}

compensated_cycle compensate(const cycle& c, const delta_n_model& dn) noexcept {
  const double delta_n_dps = dn.eval(c.temp_c);
  return {c.time_s, c.rate_dps - delta_n_dps, c.bias_dps, c.temp_c, delta_n_dps};
}

compensation_summary summarize(std::span<const compensated_cycle> cycles, double window_s) {
  assert(!cycles.empty());
  std::vector<double> t(cycles.size());
  std::vector<double> w(cycles.size());
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    t[i] = cycles[i].time_s;
    w[i] = cycles[i].rate_dps;
  }
  const auto s = analysis::mean_and_std(w);
  compensation_summary out;
  out.cycles = s.n;
  out.mean_dps = s.mean;
  out.std_dps = s.std;
  out.stderr_dps = s.std / std::sqrt(static_cast<double>(s.n));
  out.stderr_correlated_dps = correlated_stderr(w, out.stderr_dps).stderr_dps;
  out.drift_window_s = window_s;
  if (const auto r = analysis::moving_mean_extremes(t, w, window_s)) out.drift_dps = r->range();
  out.duration_s = t.back() - t.front();
  return out;
}

}  // namespace gyroflip::method
