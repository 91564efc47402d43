/// \file
/// \brief Confidence intervals of Allan-family deviations: power-law noise identification,
/// equivalent degrees of freedom (EDF) and chi-squared bounds (NIST SP1065 sections 5.2-5.6).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "gyroflip/analysis/allan.hpp"

namespace gyroflip::analysis {

/// Quantile of the chi-squared distribution with `dof` > 0 degrees of freedom at probability
/// `p` in (0, 1): inverse of the regularised lower incomplete gamma P(dof/2, x/2), by Newton
/// steps safeguarded by bisection (relative accuracy ~1e-12).
[[nodiscard]] double chi2_quantile(double p, double dof);

/// The chi-squared distribution function P(chi^2_dof <= x) = P(dof/2, x/2), the regularised lower
/// incomplete gamma (Abramowitz & Stegun 26.4.19; series and continued fraction, Numerical
/// Recipes 6.2). 0 for x <= 0; NaN for dof <= 0.
[[nodiscard]] double chi2_cdf(double x, double dof);

/// Quantile of Student's t distribution with `dof` > 0 degrees of freedom at probability `p` in
/// (0, 1) (NaN outside, or for dof <= 0): the t CDF from the regularised incomplete beta,
/// 1 - I_x(dof/2, 1/2)/2 with x = dof/(dof + t^2) (Abramowitz & Stegun 26.7.1 and 26.5.8, its
/// continued fraction by Lentz's method), inverted by bisection to 1e-12 relative. Used for the
/// 68.3 % intervals of a few runs' dN and the reproduction's family-wise limits; t(0.975, 10) =
/// 2.228 (NIST/SEMATECH e-Handbook, §1.3.6.7.2).
[[nodiscard]] double student_t_quantile(double p, double dof);

/// Student's t at the one-sigma probability 0.841345 (Phi(1)): the factor that turns a standard
/// error with `dof` degrees of freedom into a 68.3 % two-sided interval half-width (1.8373 for 1,
/// 1.3213 for 2, -> 1 as dof grows). 1 for dof = 0 (no degrees of freedom: not an interval).
[[nodiscard]] double t_one_sigma(double dof);

/// Power-law noise exponent alpha (S_y ~ f^alpha: 2 WPM, 1 FPM, 0 WFM, -1 FFM, -2 RWFM; for a
/// gyro 0 is angle random walk, -1 bias instability, -2 rate random walk) at averaging factor m,
/// by the lag-1 autocorrelation method (Riley & Greenhall 2004; SP1065 section 5.6): the phase
/// decimated by m is differenced d times until rho = r1/(1 + r1) < 0.25 (d <= 2), then
/// alpha = 2 - round(2 rho) - 2 d, clamped to [-2, 2]; at most the first 2^20 decimated points
/// are used. Returns nullopt when fewer than 30 decimated points remain (too few to tell).
[[nodiscard]] std::optional<int> noise_alpha_lag1(std::span<const double> phase, std::size_t m);

/// The noise identification `add_confidence` uses at factor m for statistic k: lag-1
/// autocorrelation with 30 decimated points or more; with 5 to 29, the B1 ratio (SP1065 section
/// 5.5: standard variance over Allan variance of the frequency averages at this tau, against
/// Barnes' B1(N, mu) with geometric-mean boundaries), and for phase noise R(n) = MVAR/AVAR to tell
/// white from flicker PM, as Stable32 does. Stable32's choices, read from its tables
/// (docs/ANALYSIS.md, "Noise identification"): N of B1(N, mu) the number of averages for ADEV and
/// HDEV, the number of frequency data for the other kinds; nullopt (type carried from a shorter
/// tau) beyond half the kind's largest all-tau factor (span/10 ADEV, HDEV; span/8 OADEV, MDEV,
/// TDEV, OHDEV; span/6 MTOTDEV, TTOTDEV, HTOTDEV; span/4 TOTDEV). nullopt below 5 points.
[[nodiscard]] std::optional<int> noise_alpha(std::span<const double> phase, std::size_t m,
                                             dev_kind k = dev_kind::adev);

/// Greenhall & Riley's EDF ("Uncertainty of stability variances based on finite differences",
/// PTTI 2003, as Stable32's CombinedEDF) of the d-th difference variance (d = 1 first difference,
/// 2 Allan, 3 Hadamard), modified (F = 1) or not (F = m), overlapping (stride S = m) or not
/// (S = 1), at factor m for N phase points and noise alpha: the basic sum up to J_max = 100 terms,
/// their Tables 1-3 beyond (rows alpha = 2 .. -4). nullopt where they define none: m = 0, d outside
/// 1..3, alpha outside -4..2, or alpha + 2d <= 1. 0 when N is too short for one term.
[[nodiscard]] std::optional<double> edf_greenhall(int alpha, int d, std::size_t m,
                                                  std::size_t n_phase, bool overlapping,
                                                  bool modified);

/// EDF of statistic `k` at averaging factor m for N phase points and noise `alpha`:
/// Greenhall & Riley's algorithm ("Uncertainty of stability variances based on finite
/// differences", 2003; as Stable32) for ADEV, OADEV, MDEV, TDEV, HDEV and OHDEV — the basic sum
/// directly up to J_max = 100 terms, their Tables 1-3 beyond — so one EDF costs at most ~100
/// evaluations whatever m and N. TOTDEV: the SP1065 Table 11 fit b (T/tau) - c with FM noise,
/// the SP1065 Table 5 flicker-PM formula with alpha = 1 and the OADEV EDF with white PM (as
/// Stable32: its bounds agree to 6e-4 on the GPS set); beyond m = (N-1)/2, where those fits are
/// not defined, at least 1.
/// MTOTDEV and TTOTDEV, as Stable32: the MDEV EDF up to m = 8, beyond it b (N/m) - c with
/// D. A. Howe's revised coefficients (WPM 2.16, 2.28; FPM 1.73, 2.99; WFM 1.33, 1.89; FFM 0.92,
/// 0.76; RWFM 0.79, 0.37), which replaced SP1065 Table 8's in Stable32. HTOTDEV, as Stable32: for
/// alpha <= 0 from m = 16 on, Howe et al.'s (N/m) / (b0 + b1 m/N) (PTTI 2000; WFM 0.559, 1.004 ...
/// RRFM 1.276, 3.149), otherwise SP1065 Table 5's OADEV EDF. All at least 1; on PHASE.DAT the
/// bounds are within 6.5e-4 of Stable32 1.60's wherever the noise type agrees, except HTOTDEV
/// with flicker PM (docs/ANALYSIS.md, "Intervals of the total family"). Theo1: Howe & Peppler's
/// fits in r = 0.75 m (SP1065's Theo1 EDF; 2003), checked against Monte Carlo EDFs, as Stable32's
/// Theo1 tables print no bounds. 0 for the kinds without an EDF (has_edf).
[[nodiscard]] double edf(dev_kind k, int alpha, std::size_t m, std::size_t n_phase);

/// The rule for a confidence level (`--ci`, Python's `ci`): a probability in (0, 1). Error
/// (parameter `level`) otherwise.
[[nodiscard]] status check_confidence_level(double level);

/// Whether `edf` gives kind k an EDF (and so bounds): every kind but PDEV, MTIE and TIE rms, for
/// which SP1065 gives none.
[[nodiscard]] bool has_edf(dev_kind k) noexcept;

/// Stable32's bias correction of the total deviations, by the noise type identified at each point
/// (its `alpha`, so after add_confidence): dev, ci_lo and ci_hi divided by sqrt(B), B the ratio of
/// the total variance to the variance it stands for: MTOTDEV/TTOTDEV (to MVAR) WPM 0.94, FPM 0.83,
/// WFM 0.73, FFM 0.70, RWFM 0.69; HTOTDEV (to HVAR) WFM 0.995, FFM 0.851, RWFM 0.771, none for PM
/// and at m = 1 (where it is OHDEV). Values: Riley, "Handbook of frequency stability analysis"
/// (SP1065) and Stable32 (docs/FACTS.md); Stable32's PHASE.DAT tables are met to 1e-4. No-op for
/// other kinds.
void correct_total_bias(std::vector<deviation_point>& points, dev_kind k);

/// How `add_confidence` picks each point's EDF.
enum class edf_rule {
  /// The EDF of the noise type identified at that tau, as Stable32 computes it (the default:
  /// bounds agree with Stable32's to 1e-3 wherever the identified type agrees).
  stable32,
  /// No interval narrower than the neighbouring taus allow: the smallest EDF among the types
  /// identified at the tau and at its two neighbours, and a frequency-noise type carried on where
  /// PM is read at a tau longer than one that showed frequency noise. A type misread from few
  /// points (white FM read as PM on 44 points: EDF 20 000 instead of ~64) then cannot give one
  /// point a +-0.5 % interval. The noise fit's weights use it (docs/ANALYSIS.md, "The guard").
  guarded,
};

/// Fills `edf`, `alpha`, `ci_lo`, `ci_hi` of every point: noise identified at each tau
/// (noise_alpha for kind k; the nearest shorter tau's type where a tau has too few points or lies
/// beyond half the kind's all-tau limit), the EDF by
/// `rule`, bounds at confidence `level` (two-sided; 0.683 = 1 sigma; check_confidence_level) from
/// SP1065 eqn 45:
/// dev_lo = dev sqrt(edf / chi2(1 - (1 - level)/2, edf)), dev_hi = dev sqrt(edf / chi2((1 -
/// level)/2, edf)). The decimated series of all points are collected in one pass over the phase
/// (as many as fit in 128 MB; more factors take more passes). `on_progress` reports that pass.
void add_confidence(std::vector<deviation_point>& points, dev_kind k, const phase_source& x,
                    double level, const progress_fn& on_progress = {},
                    edf_rule rule = edf_rule::stable32);

/// As above, on a phase series in memory (deg).
void add_confidence(std::vector<deviation_point>& points, dev_kind k, std::span<const double> phase,
                    double level, edf_rule rule = edf_rule::stable32);

/// As add_confidence, with a noise type the caller knows instead of one identified at each tau
/// (Stable32's manual noise-type setting): every point gets `alpha` (2 white PM, 1 flicker PM,
/// 0 white FM, -1 flicker FM, -2 random-walk FM; check_noise_alpha) and that type's EDF for
/// n_phase phase points. The intervals, and correct_total_bias after it, then depend neither on
/// the identification nor on which other taus were asked for (beyond half the all-tau limit the
/// identified type is the nearest shorter listed tau's, as in Stable32's tables).
void add_confidence(std::vector<deviation_point>& points, dev_kind k, std::size_t n_phase,
                    double level, int alpha);

/// The rule for a known noise type (`alpha` above): one of 2, 1, 0, -1, -2. Error (parameter
/// `alpha`) otherwise.
[[nodiscard]] status check_noise_alpha(int alpha);

/// deviation(k, x, taus) with add_confidence(level, rule) on it, in fewer reads of the samples:
/// ADEV and HDEV of rate samples at power-of-two factors (the block sums' path of deviation())
/// keep the first 2^20 - 1 block sums S_j of each factor m from their one read, and the noise
/// identification's decimated phase is their running sum, x_{km} = tau0 sum_{j<k} (S_j - m ybar)
/// (the same points as add_confidence reads, to rounding): one read of the samples for the curve
/// and its intervals instead of two. Otherwise the two calls, `on_progress` reporting both.
/// Errors as deviation().
[[nodiscard]] result<std::vector<deviation_point>> deviation_with_confidence(
    dev_kind k, const phase_source& x, const tau_spec& taus, double level,
    const progress_fn& on_progress = {}, edf_rule rule = edf_rule::stable32);

}  // namespace gyroflip::analysis
