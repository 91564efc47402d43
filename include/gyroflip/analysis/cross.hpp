/// \file
/// \brief Allan statistics across gaps, series and time windows: GRADEV (overlapping ADEV of a
/// series with NaN gaps), GCODEV (Groslambert codeviation of two series), the three-cornered hat
/// (three clocks' deviations from their three pairwise comparisons) and the dynamic Allan
/// deviation (DAVAR: a curve per sliding window). Used by `gyroflip adev --kind gradev`,
/// `--dynamic` and the Python module. Does not read files.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "gyroflip/analysis/allan.hpp"

namespace gyroflip::analysis {

/// GRADEV (Sesia, Tavella et al., "Estimating the Allan variance in the presence of long periods
/// of missing data and outliers", Metrologia 2008; allantools' gradev): the overlapping ADEV of
/// SP1065 eqn 11 over the terms whose three phase points exist, sqrt(sum / (2 n tau^2)), n the
/// number of such terms. NaN marks a missing sample. Angle input: a term exists when its three
/// points are finite. Rate input: a missing rate sample leaves the phase after it unknown by an
/// offset, so a term exists when no missing sample lies between its first and last point (each
/// gap-free run is integrated on its own, its mean removed). Factors as OADEV (m <= (N-1)/4);
/// points without a term are left out. Without a gap every term exists and the curve is OADEV's,
/// computed as `deviation` does. Errors: an infinite sample, one beyond
/// phase_source::max_sample_magnitude (as every deviation), tau0 not positive and finite, fewer
/// than 3 phase points, no finite sample, no factor with a term.
[[nodiscard]] result<std::vector<deviation_point>> gradev(std::span<const double> data,
                                                          input_kind in, double tau0_s,
                                                          const tau_spec& taus = {});

/// GCODEV (Lantz, Vernotte et al., "Groslambert covariance", arXiv:1904.05849; allantools'
/// gcodev): the overlapping Allan covariance of two series of one length,
/// sum_i v1_i v2_i / (2 tau^2 (N - 2m)), v the second differences of SP1065 eqn 11; `dev` is
/// sign(cov) sqrt(|cov|) (allantools returns |.|). It estimates the common clock's variance of two
/// comparisons A-B and B-C free of the uncorrelated noise of A, C and the counters. Errors: as
/// `deviation`, and series of different lengths.
[[nodiscard]] result<std::vector<deviation_point>> gcodev(std::span<const double> a,
                                                          std::span<const double> b, input_kind in,
                                                          double tau0_s, const tau_spec& taus = {});

/// The three-cornered hat (Gray & Allan 1974; Riley, "Handbook", §3.x): from the deviations of
/// the comparisons AB, BC, CA (statistic `k`, same taus), each clock's variance
/// var_A = (AB^2 + CA^2 - BC^2)/2 and cyclically; a negative estimate (more noise difference
/// than the comparisons hold) is reported as 0. Returns the curves of A, B and C, with `n` of AB.
/// Errors: as `deviation`; series of different lengths.
[[nodiscard]] result<std::array<std::vector<deviation_point>, 3>> three_cornered_hat(
    dev_kind k, std::span<const double> ab, std::span<const double> bc, std::span<const double> ca,
    input_kind in, double tau0_s, const tau_spec& taus = {});

/// One window of a dynamic Allan deviation: where it starts (s from the first sample) and its
/// curve.
struct dynamic_window {
  double start_s = 0.0;
  std::vector<deviation_point> curve;
};

/// A dynamic deviation's window and step in samples: `window_s` and `step_s` seconds (the step a
/// quarter window when not given) of a series of `n_samples` samples `tau0_s` apart, each rounded
/// to the nearest sample (halves up). Errors: not positive and finite, a window or step longer
/// than the series, a step below one sample (the window's lower limit is dynamic_deviation's).
[[nodiscard]] result<std::pair<std::size_t, std::size_t>> dynamic_samples(
    double window_s, std::optional<double> step_s, double tau0_s, std::size_t n_samples);

/// DAVAR (Galleani & Tavella, "The dynamic Allan variance", IEEE UFFC 56, 2009; Stable32's
/// dynamic stability): statistic `k` over windows of `window` samples starting every `step`
/// samples, each with the taus `taus` allows in a window. With `level`, each window's points get
/// their intervals as `deviation_with_confidence` gives them for that window alone (the noise type
/// identified in the window, the EDF of its N; confidence.hpp). Errors: window < 3 or beyond the
/// data, step 0, and those of `deviation` for the first window.
[[nodiscard]] result<std::vector<dynamic_window>> dynamic_deviation(
    dev_kind k, std::span<const double> data, input_kind in, double tau0_s, std::size_t window,
    std::size_t step, const tau_spec& taus = {}, const progress_fn& on_progress = {},
    std::optional<double> level = std::nullopt);

}  // namespace gyroflip::analysis
