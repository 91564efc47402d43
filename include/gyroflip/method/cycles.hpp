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
#include "gyroflip/method/row_source.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// The cycles of one recording plus what was seen while reading it.
struct recording_cycles {
  std::string path;
  std::vector<cycle> cycles;
  std::size_t rows = 0;
  std::size_t dwells = 0;
  bool has_temp = false;
  std::vector<metadata_entry> metadata;
  std::vector<std::string> warnings;  ///< `FILE:LINE: what`, for the caller to show
};

/// Reads `source` whole and forms its cycles with pairing `p`, in one streamed pass;
/// `on_progress(done, total)` in the source's units now and then (may be empty). Errors: the
/// source's, no rows, a single orientation, fewer than min_cycles cycles.
[[nodiscard]] result<recording_cycles> read_cycles(row_source& source, pairing p,
                                                   const progress_fn& on_progress = {});

/// The same for rows in memory; `name` names them in messages. Rows must be valid recording
/// rows.
[[nodiscard]] result<recording_cycles> cycles_of_rows(const std::string& name,
                                                      std::span<const row> rows, pairing p,
                                                      std::vector<metadata_entry> metadata = {});

}  // namespace gyroflip::method
