/// \file
/// \brief Private to the analysis module: the statistics beyond SP1065's sweepable sums, each at
/// one averaging factor m on a series held in memory: the total variances MTOT and HTOT (the
/// per-window detrended, reflected estimators of SP1065 eqns 27 and 29) by one FFT pass per block
/// of windows, Theo1 (eqn 30), PDEV (Vernotte et al. 2016), MTIE and TIE rms (ITU-T G.810).
/// Each returns the sum or value its statistic is made of and its term count (0: m too large).
/// docs/ANALYSIS.md, "The extended statistics", derives the algorithms.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "gyroflip/core/progress.hpp"

namespace gyroflip::analysis::detail {

/// A sum of squares and its number of terms (Stable32's "#").
struct sum_terms {
  long double sum = 0.0L;
  std::size_t n = 0;
};

/// The total-variance sum of series v at factor m (window L = 3m): for every window i of L points
/// (N - 3m + 1 of them), w = v[i, i + L) less its linear trend (the slope between the means of its
/// first and last floor(L/2) points), reflected to rev(w) w rev(w) (9m points), and the 6m second
/// differences d_j of its m-point sums: sum over windows and j of d_j^2. MTOT is this on the phase
/// (SP1065 eqn 27: MTOT = sum / (6m m^2 2 m^2 tau0^2 n)), HTOT on the frequency (eqn 29).
/// Exact in real arithmetic; by FFT per block of windows after removing the block's linear trend
/// (relative rounding ~1e-12, tested against the direct sum).
[[nodiscard]] sum_terms total_sum(std::span<const double> v, std::size_t m);

/// Theo1's sum (SP1065 eqn 30), m even: sum over i < N - m and d < m/2 of
/// (x_i - x_{i-d+m/2} + x_{i+m} - x_{i+d+m/2})^2 / (m/2 - d); n = (N - m) m / 2 terms. Term by
/// term, on all cores.
[[nodiscard]] sum_terms theo1_sum(std::span<const double> x, std::size_t m);

/// Theo1's sums at the factors ms (odd, < 2 or >= N: no terms): below m = 128 term by term,
/// beyond by prefix sums and FFT correlations (docs/ANALYSIS.md, "Theo1 by FFT"), the factors
/// side by side on all cores; a factor whose rounding bound exceeds 1e-9 of its sum (a phase
/// far from a line against its fluctuations at that m) term by term.
[[nodiscard]] std::vector<sum_terms> theo1_sums(std::span<const double> x,
                                                std::span<const std::size_t> ms,
                                                const progress_fn& progress = {});

/// PDEV's sum (Vernotte, Lenczner, Bourgeois, Rubiola 2016, eqn 13): over i < N - 2m of
/// [sum_{k<m} ((m-1)/2 - k)(x_{i+k} - x_{i+k+m})]^2; n = N - 2m (m >= 2).
[[nodiscard]] sum_terms pdev_sum(std::span<const double> x, std::size_t m);

/// MTIE at m: the largest max - min of x over any m + 1 consecutive points (N - m windows), by
/// a monotonic deque (O(N), O(m) memory).
[[nodiscard]] sum_terms mtie_value(std::span<const double> x, std::size_t m);

/// TIE rms' sum: sum over i < N - m of (x_{i+m} - x_i)^2.
[[nodiscard]] sum_terms tie_sum(std::span<const double> x, std::size_t m);

}  // namespace gyroflip::analysis::detail
