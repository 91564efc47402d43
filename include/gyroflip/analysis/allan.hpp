/// \file
/// \brief The Allan-deviation family of NIST SP1065 (Riley 2008): ADEV, OADEV, MDEV, TDEV,
/// HDEV, OHDEV and TOTDEV, for rate data (gyro output in deg/s, "fractional frequency" in
/// SP1065) or angle data (deg, "phase"). Results are in the unit of the rate (deg/s), TDEV in
/// the unit of the angle (deg).
///
/// The input kind has no default: allantools' phase-by-default convention silently gives wrong
/// answers for rate data (allantools issue #121). Used by `gyroflip adev`, `gyroflip noise` and
/// the calibration's correlated standard error.
///
/// Every statistic is computed on a `phase_source` (phase_source.hpp), which rebuilds the phase
/// block by block, so memory does not grow with the length of a file-backed series; the
/// span-based functions below wrap their span in a source. Memory beyond the source's tables:
/// per thread a window of at most 4096 + 2^17 phase points and 4096 points per far stream (two
/// or three streams per averaging factor above 65536 for OADEV/TOTDEV, 43690 for MDEV/OHDEV), a
/// few MB in all (docs/ANALYSIS.md, "How the deviations are computed, and memory").
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/analysis/sample_source.hpp"
#include "gyroflip/core/result.hpp"

namespace gyroflip::analysis {

enum class dev_kind {
  adev,
  oadev,
  mdev,
  tdev,
  hdev,
  ohdev,
  totdev,
  mtotdev,  ///< modified total (SP1065 eqn 27)
  ttotdev,  ///< time total: tau MTOTDEV / sqrt(3) (eqn 28)
  htotdev,  ///< Hadamard total (eqn 29), OHDEV at m = 1 as Stable32
  theo1,    ///< Theo1 (eqn 30), even m, tau = 0.75 m tau0
  pdev,     ///< parabolic (Vernotte et al. 2016), OADEV at m = 1
  mtie,     ///< maximum time interval error (ITU-T G.810), in the angle unit
  tierms,   ///< rms time interval error, in the angle unit
};

/// Every kind, in the order above.
inline constexpr dev_kind all_dev_kinds[] = {
    dev_kind::adev,  dev_kind::oadev,  dev_kind::mdev,    dev_kind::tdev,    dev_kind::hdev,
    dev_kind::ohdev, dev_kind::totdev, dev_kind::mtotdev, dev_kind::ttotdev, dev_kind::htotdev,
    dev_kind::theo1, dev_kind::pdev,   dev_kind::mtie,    dev_kind::tierms};

/// What gyroflip knows of one statistic, apart from its algorithm: the one table (dev_table)
/// that the library, the command line and Python read (issue 34, item 8), so that a kind's name,
/// limits, intervals and unit are said once.
struct dev_facts {
  dev_kind kind;
  std::string_view name;       ///< allantools' and Stable32's short name
  std::string_view reference;  ///< where its formula comes from
  /// Computed on the whole phase in memory (8 bytes a point) by its own algorithm (extended.hpp);
  /// the SP1065 sums of the others stream over the phase in bounded memory.
  bool extended;
  /// In the angle unit (deg): the time-error statistics TDEV (SP1065 eqn 15), TTOTDEV (eqn 28),
  /// MTIE and TIE rms (ITU-T G.810, of x itself); the others in the rate unit.
  bool angle_unit;
  bool edf;              ///< has an equivalent number of degrees of freedom: chi^2 intervals
  bool bias_correction;  ///< Stable32's bias correction by noise type (MTOTDEV, TTOTDEV, HTOTDEV)
  /// Stable32's largest averaging factor: m <= (N - 1) / span_divisor for N phase points.
  unsigned span_divisor;
  /// The fewest phase points with one term at factor m: need_per_m * m + need_extra.
  unsigned need_per_m;
  unsigned need_extra;
  bool even_m_only;   ///< Theo1: defined for even m (SP1065 eqn 30)
  double tau_factor;  ///< tau = tau_factor m tau0 (Theo1: 0.75)
};

/// Every kind's facts, in the order of dev_kind (the limits are Stable32's; averaging_factors).
inline constexpr dev_facts dev_table[] = {
    {dev_kind::adev, "adev", "SP1065 eqn 7", false, false, true, false, 5, 2, 1, false, 1.0},
    {dev_kind::oadev, "oadev", "SP1065 eqn 11", false, false, true, false, 4, 2, 1, false, 1.0},
    {dev_kind::mdev, "mdev", "SP1065 eqn 14", false, false, true, false, 4, 3, 0, false, 1.0},
    {dev_kind::tdev, "tdev", "SP1065 eqn 15", false, true, true, false, 4, 3, 0, false, 1.0},
    {dev_kind::hdev, "hdev", "SP1065 eqn 17", false, false, true, false, 5, 3, 1, false, 1.0},
    {dev_kind::ohdev, "ohdev", "SP1065 eqn 18", false, false, true, false, 4, 3, 1, false, 1.0},
    {dev_kind::totdev, "totdev", "SP1065 eqn 25", false, false, true, false, 2, 1, 1, false, 1.0},
    {dev_kind::mtotdev, "mtotdev", "SP1065 eqn 27", true, false, true, true, 3, 3, 0, false, 1.0},
    {dev_kind::ttotdev, "ttotdev", "SP1065 eqn 28", true, true, true, true, 3, 3, 0, false, 1.0},
    {dev_kind::htotdev, "htotdev", "SP1065 eqn 29", true, false, true, true, 3, 3, 1, false, 1.0},
    {dev_kind::theo1, "theo1", "SP1065 eqn 30", true, false, true, false, 1, 1, 1, true, 0.75},
    {dev_kind::pdev, "pdev", "Vernotte et al. 2016 eqn 13", true, false, false, false, 4, 2, 1,
     false, 1.0},
    {dev_kind::mtie, "mtie", "ITU-T G.810", true, true, false, false, 1, 1, 1, false, 1.0},
    {dev_kind::tierms, "tierms", "ITU-T G.810", true, true, false, false, 4, 1, 1, false, 1.0},
};

/// The facts of statistic k (its row of dev_table).
[[nodiscard]] constexpr const dev_facts& facts(dev_kind k) noexcept {
  return dev_table[static_cast<std::size_t>(k)];
}

/// True for the kinds computed on the whole phase in memory (dev_facts::extended).
[[nodiscard]] constexpr bool is_extended(dev_kind k) noexcept {
  return facts(k).extended;
}

[[nodiscard]] constexpr std::string_view to_string(dev_kind k) noexcept {
  return facts(k).name;
}
[[nodiscard]] std::optional<dev_kind> parse_dev_kind(std::string_view name) noexcept;

/// The kinds' names joined by `sep` ("adev|oadev|..."), for option lists and messages.
[[nodiscard]] std::string dev_kind_names(std::string_view sep);

/// Which averaging factors m (tau = m tau0) to evaluate.
struct tau_spec {
  enum class set { octave, decade, all, list };
  set kind = set::octave;
  std::vector<std::size_t> factors;  ///< for `list`: averaging factors (>= 1)
};

/// Parses `octave`, `decade`, `all` or a comma-separated list of averaging factors.
[[nodiscard]] result<tau_spec> parse_tau_spec(std::string_view text);

/// One point of a deviation curve. Confidence fields are NaN until confidence.hpp fills them.
struct deviation_point {
  std::size_t m = 0;   ///< averaging factor
  double tau_s = 0.0;  ///< m * tau0
  double dev = 0.0;    ///< the deviation (deg/s; TDEV in deg)
  std::size_t n = 0;   ///< number of terms in the sum (Stable32's "#" column)
  double edf = 0.0;    ///< equivalent degrees of freedom (0 = not computed)
  double ci_lo = 0.0;  ///< lower confidence bound of dev
  double ci_hi = 0.0;  ///< upper confidence bound of dev
  int alpha = 0;       ///< identified power-law noise exponent (S_y ~ f^alpha)
};

/// Averaging factors of `spec` for a phase series of `n_phase` points and statistic `k`,
/// limited as Stable32 does: m <= (N-1)/5 for ADEV and HDEV, (N-1)/4 for OADEV, MDEV, TDEV, OHDEV,
/// PDEV and TIE rms, (N-1)/3 for MTOTDEV, TTOTDEV and HTOTDEV (their windows of 3m), (N-1)/2 for
/// TOTDEV, N - 1 for Theo1 and MTIE (a `list` is limited to factors with at least one term).
/// Theo1 keeps even factors only. `decade` is 1, 2, 4, 10, 20, 40, 100, ... (Stable32).
[[nodiscard]] std::vector<std::size_t> averaging_factors(const tau_spec& spec, dev_kind k,
                                                         std::size_t n_phase);

/// The deviation `k` of phase `x` (N points, spacing tau0_s) at averaging factor m, with its
/// number of terms (0 when m is too large). Formulas (x_i, i = 0..N-1, tau = m tau0):
/// - ADEV   (SP1065 eqn 7):  sum over non-overlapping k of (x_{(k+2)m} - 2x_{(k+1)m} + x_{km})^2 /
/// (2 tau^2 n)
/// - OADEV  (eqn 11): all i of (x_{i+2m} - 2x_{i+m} + x_i)^2 / (2 tau^2 (N - 2m))
/// - MDEV   (eqn 14): [sum_{i=j}^{j+m-1} (x_{i+2m} - 2x_{i+m} + x_i)]^2 / (2 m^2 tau^2 (N - 3m +
/// 1))
/// - TDEV   (eqn 15): tau MDEV / sqrt(3)
/// - HDEV   (eqn 17): non-overlapping third differences squared / (6 tau^2 n)
/// - OHDEV  (eqn 18): all third differences (x_{i+3m} - 3x_{i+2m} + 3x_{i+m} - x_i)^2 / (6 tau^2 (N
/// - 3m))
/// - TOTDEV (eqn 25): OADEV terms centred on every interior point of x extended by reflection
///   at both ends (x*_{-j} = 2x_0 - x_j, x*_{N-1+j} = 2x_{N-1} - x_{N-1-j}), over N - 2 terms,
///   for every m up to N - 1.
/// - MTOTDEV (eqn 27): every window of 3m phase points, detrended by the slope between the means
///   of its halves and reflected to 9m points; the 6m MDEV-type terms of each, averaged:
///   sum / (6m m^2 2 m^2 tau^2 (N - 3m + 1)) with m-point sums; TTOTDEV = tau MTOTDEV / sqrt(3).
/// - HTOTDEV (eqn 29): the same windows of 3m frequency averages y_i = (x_{i+1} - x_i)/tau0,
///   Hadamard terms: sum / (36 m^3 (N - 3m)); OHDEV at m = 1 (Stable32).
/// - Theo1 (eqn 30): sum_{i<N-m} sum_{d<m/2} (x_i - x_{i-d+m/2} + x_{i+m} - x_{i+d+m/2})^2 /
///   (m/2 - d) / (0.75 (N - m) tau^2), tau reported as 0.75 m tau0, n = (N - m) m/2.
/// - PDEV (Vernotte et al. 2016 eqn 13): 72 sum_i [sum_{k<m} ((m-1)/2 - k)(x_{i+k} - x_{i+k+m})]^2
///   / ((N - 2m) m^4 tau^2); OADEV at m = 1.
/// - MTIE: max over windows of m + 1 points of (max - min); TIE rms: sqrt(mean (x_{i+m} - x_i)^2),
///   n = N - m (both in the angle unit).
/// Squared differences are summed in double over blocks of 4096 terms and the block sums in long
/// double; MDEV's inner sum slides by one term per step and is recomputed exactly every 2^20
/// steps (relative rounding ~1e-13, tested against all-long-double references). The extended
/// kinds' algorithms (docs/ANALYSIS.md, "The extended statistics") are tested against direct sums.
/// Returns n = 0 when m is too large, tau0 is not positive or x has a non-finite value.
struct raw_deviation {
  double dev = 0.0;
  std::size_t n = 0;
};
[[nodiscard]] raw_deviation deviation_at(dev_kind k, std::span<const double> x, double tau0_s,
                                         std::size_t m);

/// The whole curve of statistic `k` on the phase `x` (deg; tau0 from the source): one sweep over
/// the phase for all averaging factors of OADEV, TOTDEV, OHDEV, MDEV and TDEV (factors above
/// 2^17 / order read their own streams, at most 32 of them per sweep); ADEV and HDEV read the phase
/// decimated by each m. All on every core. `on_progress(done, total)` reports work items
/// (progress line); may be empty. Confidence intervals are not filled here (confidence.hpp).
/// Errors: fewer than 3 phase points, no averaging factor left.
[[nodiscard]] result<std::vector<deviation_point>> deviation(dev_kind k, const phase_source& x,
                                                             const tau_spec& taus,
                                                             const progress_fn& on_progress = {});

/// The whole curve of statistic `k` on `data` (rate or angle samples spaced tau0_s apart).
/// Errors: fewer than 3 phase points, tau0 not positive and finite, non-finite data, no
/// averaging factor left.
[[nodiscard]] result<std::vector<deviation_point>> deviation(dev_kind k,
                                                             std::span<const double> data,
                                                             input_kind in, double tau0_s,
                                                             const tau_spec& taus,
                                                             const progress_fn& on_progress = {});

/// The whole curve of statistic `k` on `samples`, for callers that need no phase afterwards (no
/// confidence intervals): as deviation() on phase_source::make(samples, in, tau0_s), but ADEV and
/// HDEV of rate samples at factors that are all powers of two come from one read of the samples
/// (block sums: decimate.hpp, octave_block_sums; docs/ANALYSIS.md) instead of the phase tables'
/// two reads and a sweep; equal to the phase path to ~1e-13 relative. Errors as deviation().
[[nodiscard]] result<std::vector<deviation_point>> deviation(dev_kind k,
                                                             const sample_source& samples,
                                                             input_kind in, double tau0_s,
                                                             const tau_spec& taus,
                                                             const progress_fn& on_progress = {});

/// As `deviation`, on a phase series already built (deg; from phase_from_rate for rate data).
[[nodiscard]] result<std::vector<deviation_point>> deviation_of_phase(
    dev_kind k, std::span<const double> x, double tau0_s, const tau_spec& taus,
    const progress_fn& on_progress = {});

/// An averaging factor that was asked for (a `list` of factors) but has no point in the curve.
struct dropped_factor {
  std::size_t m = 0;
  double tau_s = 0.0;
  std::string why;
};

/// The factors of a `list` spec that `points` (the curve of statistic `k` on `n_phase` phase
/// points spaced `tau0_s`) does not have, each with the reason: a statistic needs at least one
/// difference of its order at m, i.e. ADEV, OADEV and PDEV 2m + 1 phase points, MDEV, TDEV,
/// MTOTDEV and TTOTDEV 3m, HDEV, OHDEV and HTOTDEV 3m + 1, TOTDEV (reflected), MTIE and TIE rms
/// m + 1, Theo1 m + 1 and an even m. Empty for octave, decade and all.
[[nodiscard]] std::vector<dropped_factor> dropped_factors(const tau_spec& spec,
                                                          std::span<const deviation_point> points,
                                                          dev_kind k, std::size_t n_phase,
                                                          double tau0_s);

/// allantools-style shorthands (octave taus unless given).
[[nodiscard]] result<std::vector<deviation_point>> oadev(std::span<const double> data,
                                                         input_kind in, double tau0_s,
                                                         const tau_spec& taus = {});

}  // namespace gyroflip::analysis
