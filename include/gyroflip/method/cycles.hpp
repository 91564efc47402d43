/// \file
/// \brief The pairing pipeline: the rows of any source (method/row_source.hpp) -> dwells ->
/// cycles with a pairing, and the checks every recording passes before the method uses it.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/metadata.hpp"
#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/method/flip_pair.hpp"
#include "gyroflip/method/row_source.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// The cycles of one recording plus what was seen while reading it.
struct recording_cycles {
  std::string path;
  std::vector<cycle> cycles;
  std::size_t rows = 0;
  std::size_t dwells = 0;    ///< dwells at the pair's two positions
  position_table positions;  ///< the source's table
  flip_pair pair;            ///< the two positions the pairing used (flip_pair.hpp)
  bool has_temp = false;
  /// Each paired dwell's rate (deg/s) in order: the run's content print (cycle_print.hpp).
  std::vector<double> dwell_rates;
  std::vector<metadata_entry> metadata;
  std::vector<std::string> warnings;  ///< `FILE:LINE: what`, for the caller to show
};

/// Reads `source` whole and forms its cycles with pairing `p`, in one streamed pass;
/// `on_progress(done, total)` in the source's units now and then (may be empty). Errors: the
/// source's, no rows, a table without the pair (flip_pair_of), a single orientation, fewer than
/// min_cycles cycles. Dwells at the table's other positions are left out, with a warning.
[[nodiscard]] result<recording_cycles> read_cycles(row_source& source, pairing p,
                                                   const progress_fn& on_progress = {});

/// The same for rows in memory at the positions of `positions`; `name` names them in messages.
/// Rows must be valid recording rows.
[[nodiscard]] result<recording_cycles> cycles_of_rows(
    const std::string& name, std::span<const row> rows, pairing p,
    std::vector<metadata_entry> metadata = {},
    const position_table& positions = position_table::pair_0_180());

}  // namespace gyroflip::method
