/// \file
/// \brief Private to the analysis module: the sums behind the overlapping statistics (OADEV,
/// TOTDEV, OHDEV, MDEV) for many averaging factors in one sweep over a phase source.
///
/// The term index range is cut into chunks of 2^20 (the work items of the threads) and blocks
/// of 4096. Per block, every factor's terms are summed while the block's phase is in cache:
/// factors with order * m <= 2^17 read it from one sliding window x[b, b + 4096 + order m_max)
/// ("near" factors), each larger factor from streams at offsets j m, shared between factors
/// (for octave taus the 2m stream of one factor is the m stream of the next). Results do not
/// depend on the number of threads: block sums are fixed and added in chunk order.
#pragma once

#include <cstddef>
#include <vector>

#include "gyroflip/analysis/phase_source.hpp"

namespace gyroflip::analysis::detail {

/// One averaging factor of a sweep and its term indices [lo, hi).
struct term_range {
  std::size_t m = 0;
  std::ptrdiff_t lo = 0;
  std::ptrdiff_t hi = 0;
};

/// For each factor: sum over i in [lo, hi) of the squared `order`-th difference at lag m
/// (order 2: x*_{i+2m} - 2 x*_{i+m} + x*_i, SP1065 eqn 11; order 3: eqn 18). With `reflect`,
/// x* is x reflected at both ends (x*_{-j} = 2x_0 - x_j, x*_{N-1+j} = 2x_{N-1} - x_{N-1-j},
/// SP1065 eqn 25) and i may be negative; without, every index must lie in [0, N).
[[nodiscard]] std::vector<long double> difference_sums(const phase_source& x, std::size_t order,
                                                       bool reflect,
                                                       const std::vector<term_range>& factors,
                                                       const progress_fn& on_progress);

/// For each factor m (3m <= N): sum over j in [0, N - 3m + 1) of the squared MDEV inner sum
/// s_j = sum_{i=j}^{j+m-1} (x_{i+2m} - 2x_{i+m} + x_i) (SP1065 eqn 14). s slides by one term per
/// step; it is recomputed exactly (from block phase sums, phase_source::offset_sum) at the start
/// of every chunk, so rounding grows over at most 2^20 steps (~1e-13 relative).
[[nodiscard]] std::vector<long double> mdev_sums(const phase_source& x,
                                                 const std::vector<std::size_t>& factors,
                                                 const progress_fn& on_progress);

}  // namespace gyroflip::analysis::detail
