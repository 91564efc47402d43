/// \file
/// \brief The drift metrics the paper uses: mean and standard deviation of a series, and
/// the range (max - min) of its moving mean over a time window.
///
/// Paper Figs. 4-10 quote the mean and std of the compensated output; its conclusion quotes
/// "a bias drift of 0.002 deg/s over 2.5 h", which gyroflip measures as the range of a 100-s
/// moving mean (`gyroflip compensate --json`, key `drift_dps`).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace gyroflip::analysis {

/// Sample mean and standard deviation (n - 1 denominator; std = 0 for n = 1).
struct mean_std {
  double mean = 0.0;
  double std = 0.0;
  std::size_t n = 0;
};

/// Two-pass mean and sample standard deviation (no cancellation from running sums).
/// Precondition: `values` is not empty.
[[nodiscard]] mean_std mean_and_std(std::span<const double> values);

/// The upper median: the element of rank n/2 once sorted (the median for odd n, the upper of the
/// middle two for even n), in O(n) (std::nth_element). Precondition: `values` is not empty.
[[nodiscard]] double upper_median(std::vector<double> values);

/// Extremes of a moving mean.
struct moving_mean_range {
  double min = 0.0;
  double max = 0.0;
  double window_s = 0.0;
  std::size_t windows = 0;  ///< number of complete windows evaluated
  [[nodiscard]] double range() const noexcept { return max - min; }
};

/// Min and max of the trailing moving mean over `window_s` seconds: for every sample j with
/// t_j - t_0 >= window_s, the mean of the values with t_j - window_s < t_i <= t_j.
/// Only complete windows count; returns nullopt when the record is shorter than one window, or
/// when the window is below the resolution of the time stamps (t_j - window_s == t_j for some j).
/// Preconditions: equal sizes, `time_s` non-decreasing, `window_s` > 0. O(n).
[[nodiscard]] std::optional<moving_mean_range> moving_mean_extremes(std::span<const double> time_s,
                                                                    std::span<const double> values,
                                                                    double window_s);

}  // namespace gyroflip::analysis
