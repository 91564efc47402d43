/// \file
/// \brief Mean/std, the upper median and moving-mean extremes (see drift.hpp).
#include "gyroflip/analysis/drift.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace gyroflip::analysis {

double upper_median(std::vector<double> values) {
  assert(!values.empty());
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

mean_std mean_and_std(std::span<const double> values) {
  assert(!values.empty());
  const auto n = values.size();
  double sum = 0.0;
  for (double v : values) sum += v;
  const double mean = sum / static_cast<double>(n);
  // Second pass on deviations; the correction term removes the rounding error of `mean`.
  double ss = 0.0;
  double corr = 0.0;
  for (double v : values) {
    const double d = v - mean;
    ss += d * d;
    corr += d;
  }
  const double var =
      n > 1 ? (ss - corr * corr / static_cast<double>(n)) / static_cast<double>(n - 1) : 0.0;
  return {mean, std::sqrt(std::max(var, 0.0)), n};
}

std::optional<moving_mean_range> moving_mean_extremes(std::span<const double> time_s,
                                                      std::span<const double> values,
                                                      double window_s) {
  assert(time_s.size() == values.size() && window_s > 0.0);
  const std::size_t n = values.size();
  if (n == 0) return std::nullopt;
  moving_mean_range out{};
  out.window_s = window_s;
  std::size_t lo = 0;  // first index inside the window ending at j
  double sum = 0.0;    // re-summed per window start move; Kahan keeps long records exact enough
  double comp = 0.0;
  const auto add = [&](double v) {
    const double y = v - comp;
    const double t = sum + y;
    comp = (t - sum) - y;
    sum = t;
  };
  for (std::size_t j = 0; j < n; ++j) {
    // A window below the resolution of the time stamps (t - w == t: Unix-epoch nanoseconds, or
    // w = 1e-300) has no meaning there; without this test every sample would leave its own
    // window and `lo` would run past j (and past the end).
    if (time_s[j] - window_s == time_s[j]) return std::nullopt;
    add(values[j]);
    while (lo < j && time_s[lo] <= time_s[j] - window_s) add(-values[lo++]);
    if (time_s[j] - time_s[0] < window_s) continue;
    const double m = sum / static_cast<double>(j - lo + 1);
    if (out.windows == 0) out.min = out.max = m;
    out.min = std::min(out.min, m);
    out.max = std::max(out.max, m);
    ++out.windows;
  }
  if (out.windows == 0) return std::nullopt;
  return out;
}

}  // namespace gyroflip::analysis
