/// \file
/// \brief Private to the analysis module: how many threads a pass over the phase uses; the pass
/// itself is the library's parallel helper (core/parallel.hpp).
#pragma once

#include <algorithm>
#include <cstddef>

#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/core/parallel.hpp"

namespace gyroflip::analysis::detail {

/// Threads for a pass over n points: 1 below 2^16 points (starting threads would cost more than
/// it saves), else every core up to 8.
inline std::size_t worker_count(std::size_t n_points) {
  if (n_points < (std::size_t{1} << 16)) return 1;
  return std::min<std::size_t>(hardware_threads(), 8);
}

// The pass over numbered items and the part progress are the library's one parallel helper
// (core/parallel.hpp), which also passes on what a work item throws.
using gyroflip::for_each_item;
using gyroflip::part_progress;

}  // namespace gyroflip::analysis::detail
