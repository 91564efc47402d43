/// \file
/// \brief Several calibration runs together (see runs.hpp).
#include "gyroflip/method/runs.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace gyroflip::method {

result<std::optional<delta_n_model>> fit_runs_model(std::span<const calibration> runs,
                                                    std::optional<std::size_t> degree) {
  if (runs.size() < 2) return std::optional<delta_n_model>{};
  std::vector<delta_n_point> pts;
  bool all_have_temp = true;
  for (const auto& r : runs) {
    all_have_temp = all_have_temp && !std::isnan(r.temp_c);
    pts.push_back({r.temp_c, r.delta_n_dps, r.stderr_correlated_dps});
  }
  double span_c = 0.0;
  if (all_have_temp) {
    const auto [lo, hi] = std::minmax_element(
        pts.begin(), pts.end(), [](const auto& a, const auto& b) { return a.temp_c < b.temp_c; });
    span_c = hi->temp_c - lo->temp_c;
  } else {
    for (auto& p : pts) p.temp_c = 0.0;  // a constant needs no temperature
  }
  auto m = fit_delta_n_random_effects(pts, degree.value_or(span_c >= min_model_span_c ? 1 : 0));
  if (!m) return m.err();
  if (!all_have_temp) m->t_ref_c = m->temp_min_c = m->temp_max_c = no_value;
  return std::optional<delta_n_model>{std::move(*m)};
}

double pooled_correlated_stderr(std::span<const calibration> runs) {
  double num = 0.0;
  double n = 0.0;
  for (const auto& r : runs) {
    const double ni = static_cast<double>(r.cycles);
    num += ni * ni * r.stderr_correlated_dps * r.stderr_correlated_dps;
    n += ni;
  }
  return std::sqrt(num) / n;
}

}  // namespace gyroflip::method
