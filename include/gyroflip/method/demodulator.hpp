/// \file
/// \brief Demodulators (issue 33): what turns a recording's dwells into estimates, behind one
/// interface, and the one table of schemes that names them (the `--pairing` values).
///
/// A demodulator takes dwells (method/dwells.hpp: a row stream's dwells, or a rig's) one at a
/// time and gives an estimate whenever one is final; `flush` gives what the end of the data
/// completes. Each scheme states its **noise transfer**: the weights its interior estimate puts on
/// the dwells around it (its kernel), from which follow how white, flicker and random-walk noise
/// of the dwells map into the estimate's variance and covariance (below), the series' short-tau
/// Allan shape and the stationarity test's white-noise reference. So the noise fit
/// (analysis::noise_series), the stationarity test and the planner read the scheme's transfer
/// instead of a hard-coded abba.
///
/// Adding a scheme: a class implementing `demodulator`, its kernel, and one row of `schemes()`
/// (docs/ARCHITECTURE.md, "Adding a scheme").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/analysis/noise_fit.hpp"
#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/flip_pair.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// A demodulator's noise transfer: the signed weights its interior estimate of the rate term
/// (r) and of the bias (c) puts on consecutive dwells, the first weight on the dwell
/// `kernel_offset` places before its cycle's first dwell, and the cycle's length in dwells (the
/// step between consecutive estimates). Signs are those of the cycle's first dwell at the +1
/// position. Estimates at the record's edges have their own, shorter kernels (METHOD-NOTES.md).
///
/// For any noise with stationary increments whose dwell means have the gap two-sample variance
/// sigma^2(tau, S) (Barnes et al. 1971, NBS TN 394), a zero-sum kernel w has
///   var(sum_k w_k y_k) = -sum_{j != k} w_j w_k sigma^2(tau, |j - k| S)
/// (from var = -1/2 sum_jk w_j w_k E(y_j - y_k)^2 when sum w = 0, and E(y_j - y_k)^2 = 2
/// sigma^2): `rate_variance`. Under white dwell noise of variance s^2 the estimate series has
/// autocovariance s^2 gamma_h, gamma_h = sum_k w_k w_{k + h L} (L the cycle length), so
///   var = s^2 gamma_0;  std/ADEV(tau0) = sqrt(gamma_0/(gamma_0 - gamma_1))  (one-lag kernels);
///   AVAR(m cycles) = N^2 (1/tau - kappa T/tau^2) for m >= the kernel's lags, with
///   kappa = 3 sum_h h gamma_h / (gamma_0 + 2 sum_h gamma_h)
/// (the Allan variance of a moving-average series: Var(block mean) less the covariance of two
/// adjacent blocks, sum_h h gamma_h / m^2). simple: w = (1/2, -1/2), gamma_0 = 1/2, no lag, kappa
/// 0. abba: w = (-1/8, 3/8, -3/8, 1/8) from the dwell before the cycle, gamma_0 = 20/64,
/// gamma_1 = 6/64, std/ADEV sqrt(20/14) = 1.195, kappa 9/16 (docs/ANALYSIS.md, "Cycle series of
/// the abba pairing").
struct noise_transfer {
  std::vector<double> rate_kernel;  ///< weights of r on consecutive dwells
  std::vector<double> bias_kernel;  ///< weights of c on the same dwells
  std::size_t kernel_offset = 0;    ///< dwells of the kernel before the cycle's first
  std::size_t cycle_dwells = 2;     ///< dwells per estimate (the step between estimates)

  /// gamma_h of the rate estimates (lag h in cycles) under white dwell noise of unit variance.
  [[nodiscard]] double white_autocovariance(std::size_t lag_cycles) const noexcept;
  /// Covariance of (r, c) of one interior estimate under white dwell noise of unit variance:
  /// {var r, cov(r, c), var c}.
  [[nodiscard]] std::array<double, 3> white_covariance() const noexcept;
  /// std(r) / ADEV_r(tau0) of the estimate series under white dwell noise (the stationarity
  /// test's reference): sqrt(gamma_0 / (gamma_0 - gamma_1)).
  [[nodiscard]] double white_std_over_adev() const noexcept;
  /// kappa of AVAR = N^2 (1/tau - kappa T/tau^2) of the estimate series under white dwell noise
  /// (0: uncorrelated estimates, whose Allan curve is the plain N^2/tau).
  [[nodiscard]] double white_avar_deficit() const noexcept;
  /// Variance of one interior rate estimate for dwell means with the gap two-sample variance
  /// `gap_avar(lag_dwells)` (sigma^2(tau, lag S), Barnes 1971): the formula above.
  template <class GapAvar>
  [[nodiscard]] double rate_variance(GapAvar&& gap_avar) const {
    double v = 0.0;
    for (std::size_t j = 0; j < rate_kernel.size(); ++j)
      for (std::size_t k = 0; k < rate_kernel.size(); ++k)
        if (j != k) v -= rate_kernel[j] * rate_kernel[k] * gap_avar(j > k ? j - k : k - j);
    return v;
  }
};

/// Turns dwells into estimates (cycles: r, the rate term, and c, the bias, with their time and
/// temperature). Dwells must be at the positions `uses` holds, in the order recorded.
class demodulator {
 public:
  demodulator() = default;
  demodulator(const demodulator&) = default;
  demodulator(demodulator&&) = default;
  demodulator& operator=(const demodulator&) = default;
  demodulator& operator=(demodulator&&) = default;
  virtual ~demodulator() = default;

  /// The scheme's name (its row of schemes()).
  [[nodiscard]] virtual std::string_view name() const noexcept = 0;
  /// The table positions whose dwells it takes, as bits (bit i: position i). Rows at other
  /// positions are passed over as rows taken while the table turns.
  [[nodiscard]] virtual std::uint32_t uses() const noexcept = 0;
  /// Adds the next dwell; returns an estimate once one is final.
  [[nodiscard]] virtual std::optional<cycle> push(const dwell& d) = 0;
  /// End of data: the estimates still held back, one per call (call until none); then the
  /// demodulator starts afresh.
  [[nodiscard]] virtual std::optional<cycle> flush() = 0;
  /// Whether it takes dwells as the harmonic fit reads them (method::indexed_dwells): every row
  /// that is an average of several conversions a dwell of its own, and rows taken while the
  /// table turns ending a dwell (a sweep dwells twice at each end: two rows at one position are
  /// two dwells). The 0/180 schemes take maximal runs of rows at one position (false).
  [[nodiscard]] virtual bool dwell_per_row() const noexcept { return false; }
  /// A fresh copy (same scheme and positions, nothing pushed).
  [[nodiscard]] virtual std::unique_ptr<demodulator> fresh() const = 0;
};

/// One row of the table of schemes.
struct scheme {
  std::string_view name;         ///< the `--pairing` value
  std::string_view label;        ///< how a report's tables name it ("simple (paper)")
  std::string_view description;  ///< one line, with the formula's source
  const noise_transfer& (*transfer)();
  /// The named terms of dN its calibration estimates (0/180: `delta_n` alone).
  std::span<const std::string_view> (*terms)();
  /// The demodulator for a recording with this table (error naming `source` when the table
  /// lacks the positions the scheme needs).
  result<std::unique_ptr<demodulator>> (*make)(const position_table& table,
                                               const std::string& source);
};

/// The schemes, the default first. The one place a scheme is named.
[[nodiscard]] std::span<const scheme> schemes() noexcept;
/// The scheme of a pairing (its row of schemes()).
[[nodiscard]] const scheme& scheme_of(pairing p) noexcept;
/// The names of the schemes, in the table's order.
[[nodiscard]] std::vector<std::string> scheme_names();
/// The names joined by `separator` ("abba|simple"; " or ": "abba or simple").
[[nodiscard]] std::string scheme_names_joined(std::string_view separator);

/// The 0/180 demodulators (pairings `simple` and `abba`, method/pairing.hpp) on the two
/// positions of `pair`.
[[nodiscard]] std::unique_ptr<demodulator> make_flip_demodulator(pairing p, flip_pair pair = {});
/// The demodulator of scheme `p` for a recording with `table` (scheme_of(p).make).
[[nodiscard]] result<std::unique_ptr<demodulator>> make_demodulator(pairing p,
                                                                    const position_table& table,
                                                                    const std::string& source);

/// The named terms of dN of a calibration `cal` by scheme `p` (0/180: {delta_n, cal.delta_n_dps,
/// cal.stderr_correlated_dps}).
[[nodiscard]] std::vector<delta_n_term> terms_of(const calibration& cal, pairing p);

/// What the noise fit needs to know of a series of scheme `p`'s estimates spaced `cycle_s`
/// apart (their white-noise Allan shape, analysis/noise_fit.hpp).
[[nodiscard]] analysis::noise_series noise_series_of(pairing p, double cycle_s);

}  // namespace gyroflip::method
