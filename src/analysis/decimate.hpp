/// \file
/// \brief Private to the analysis module: statistics of the phase decimated by m, z_k = x_{km}:
/// the non-overlapping ADEV and HDEV sums and the decimated series of noise identification.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/phase_source.hpp"

namespace gyroflip::analysis::detail {

/// The largest averaging factor of statistic k for N phase points, as Stable32's all-tau tables
/// (averaging_factors, allan.hpp): (N-1)/5 ADEV, HDEV; (N-1)/2 TOTDEV; (N-1)/3 MTOTDEV, TTOTDEV,
/// HTOTDEV; N-1 Theo1, MTIE; (N-1)/4 the others.
std::size_t max_factor(dev_kind k, std::size_t n_phase);

/// Terms of the non-overlapping `order`-th differences of the phase decimated by m, for N phase
/// points: (N-1)/m - order + 1 (ADEV, order 2: SP1065 eqn 7; HDEV, order 3: eqn 17), or 0.
inline std::size_t decimated_terms(std::size_t n_phase, std::size_t m, std::size_t order) {
  const std::size_t groups = n_phase > 0 ? (n_phase - 1) / m : 0;
  return groups >= order ? groups - order + 1 : 0;
}

/// For each factor m: the sum over k of the squared `order`-th difference of z (order 2:
/// z_{k+2} - 2z_{k+1} + z_k, ADEV, SP1065 eqn 7; order 3: HDEV, eqn 17), for the
/// (N-1)/m - order + 1 terms that fit (none if fewer). Work items of 4096 terms per factor on
/// all cores; z is picked from contiguous reads for m < phase_source::block_points and read
/// point by point beyond (each point then rebuilds at most one block of the phase).
[[nodiscard]] std::vector<long double> decimated_sums(const phase_source& x, std::size_t order,
                                                      const std::vector<std::size_t>& factors,
                                                      const progress_fn& on_progress);

/// As decimated_sums, for rate samples y and factors that are all powers of two, without the
/// phase: x_{(k+1)m} - x_{km} = tau0 (S_k - m ybar) with S_k the sum of block k of m samples, so
/// the order-th difference of the decimated phase is tau0 times the (order-1)-th difference of
/// the block sums, and the mean cancels (docs/ANALYSIS.md, "ADEV and HDEV of rate samples from
/// block sums"). One read of the samples, in chunks on all cores, builds the pyramid of octave
/// block sums (each level the pairwise sums of the one below, of y - c with c the mean of the
/// first 1024 samples, so the sums stay small) and sums every level's squared differences; the
/// levels of 1024 samples and more are kept whole (M/512 doubles) and finished after the pass.
/// Sums in double per 4096 terms, added in long double in chunk order (thread-independent).
/// nullopt (nothing computed) when a factor is not a power of two, tau0 or a sample is outside
/// phase_source's limits (a non-finite sample among them): phase_source::make then says why.
/// With `heads`, also keeps per factor the first block sums the pass forms anyway (see
/// block_heads), from which the noise identification's decimated phase follows without a read.
struct block_heads;
[[nodiscard]] std::optional<std::vector<long double>> octave_block_sums(
    const sample_source& y, double tau0_s, std::size_t order,
    const std::vector<std::size_t>& factors, const progress_fn& on_progress,
    block_heads* heads = nullptr);

/// The first block sums of each factor m = 2^j (a power of two) of rate samples y: S_i = sum of
/// (y - offset) over block i of m samples, i < min(cap, M/m). The phase decimated by m is their
/// running sum, x_{km} = tau0 (sum_{i<k} S_i - k m (ybar - offset)) (phase_source's x, the mean
/// ybar removed): decimated_from_heads. Arrays not zeroed first (their pages are first touched by
/// the threads that write them), with room for one more point.
struct block_heads {
  std::size_t cap = 0;                          ///< in: at most this many sums per factor
  double offset = 0.0;                          ///< out: the sums are of y - offset
  std::vector<std::unique_ptr<double[]>> sums;  ///< out: per level j, or null if not asked
  std::vector<std::size_t> counts;              ///< out: per level j, the sums held
};

/// Turns level j's sums (block_heads) in place into the decimated phase x_{k 2^j},
/// k <= counts[j] (long-double running sums: phase_source's points to rounding), and returns it.
[[nodiscard]] std::span<double> decimated_from_heads(block_heads& heads, std::size_t level,
                                                     double mean, double tau0_s);

/// ADEV or HDEV (`k`) of rate samples at power-of-two factors from block sums, without the phase
/// (octave_block_sums; allan.cpp). nullopt where that does not apply (another kind, input or
/// factor; a sample or tau0 out of range): the phase path computes the curve or says what is wrong.
[[nodiscard]] std::optional<result<std::vector<deviation_point>>> deviation_from_block_sums(
    dev_kind k, const sample_source& samples, input_kind in, double tau0_s, const tau_spec& taus,
    const progress_fn& on_progress, block_heads* heads = nullptr);

/// For every factor m: z_0, z_1, ... (the first min(cap, (N-1)/m + 1) points), all collected in
/// one pass over the phase. Holds sum over factors of that many doubles.
[[nodiscard]] std::vector<std::vector<double>> decimated_prefixes(
    const phase_source& x, const std::vector<std::size_t>& factors, std::size_t cap,
    const progress_fn& on_progress);

}  // namespace gyroflip::analysis::detail
