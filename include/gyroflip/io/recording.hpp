/// \file
/// \brief Reader of recordings in the gyroflip CSV format (docs/FORMATS.md): validated rows,
/// and the cycles of a whole file.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::io {

/// Streams the rows of a recording, checking each one: `time_s` finite and non-decreasing,
/// `angle_deg` 0 or 180 (within a tolerance; empty = table turning), `rate_dps` finite, `temp_c`
/// finite when the column exists, `n_avg` a whole number >= 1 (default 1).
class recording_reader {
 public:
  /// Temperatures a recording may hold (degC): absolute zero to 1000 degC.
  static constexpr double min_temp_c = -273.15;
  static constexpr double max_temp_c = 1000.0;

  /// Largest `angle_tolerance_deg` (deg): an encoder angle further than this from its position
  /// is a table that did not reach it.
  static constexpr double max_angle_tolerance_deg = 10.0;

  /// `angle_tolerance_deg` in [0, max_angle_tolerance_deg]: an angle within it of 0 (or 360)
  /// reads as 0, within it of 180 as 180 (an encoder's reading of the two positions).
  [[nodiscard]] static result<recording_reader> open(const std::string& path,
                                                     double angle_tolerance_deg = 0.0);

  /// Reads the next row into `out`. `failed` -> `last_error()` has FILE:LINE:COL.
  [[nodiscard]] csv_reader::step next(method::row& out);
  [[nodiscard]] const error& last_error() const noexcept { return error_; }

  [[nodiscard]] bool has_temp() const noexcept { return has_temp_; }
  /// Warnings about rows that were read (`FILE:LINE: what`), e.g. a last line without newline.
  [[nodiscard]] const std::vector<std::string>& warnings() const noexcept { return warnings_; }
  [[nodiscard]] const std::vector<csv_metadata>& metadata() const noexcept {
    return csv_.metadata();
  }
  [[nodiscard]] const std::string& path() const noexcept { return csv_.path(); }
  [[nodiscard]] std::uint64_t bytes_done() const noexcept { return csv_.bytes_done(); }
  [[nodiscard]] std::uint64_t bytes_total() const noexcept { return csv_.bytes_total(); }

 private:
  // cppcheck-suppress passedByValue ; sink parameter, moved from
  explicit recording_reader(csv_reader c) noexcept : csv_(std::move(c)) {}
  csv_reader::step fail(const error& e);
  csv_reader csv_;
  bool has_temp_ = false;
  bool has_n_avg_ = false;
  double angle_tolerance_deg_ = 0.0;
  double last_time_s_ = -1e300;
  std::size_t last_time_line_ = 0;
  error error_{errc::bad_input, {}};
  std::vector<std::string> warnings_;
};

/// The cycles of one recording plus what was seen while reading it.
struct recording_cycles {
  std::string path;
  std::vector<method::cycle> cycles;
  std::size_t rows = 0;
  std::size_t dwells = 0;
  bool has_temp = false;
  std::vector<csv_metadata> metadata;
  std::vector<std::string> warnings;  ///< `FILE:LINE: what`, for the caller to show
};

/// Reads a whole recording and forms its cycles with pairing `p`; `on_progress(bytes read,
/// bytes total)` now and then (may be empty). Errors: any bad row, a single orientation, fewer
/// than method::min_cycles cycles.
[[nodiscard]] result<recording_cycles> read_cycles(const std::string& path, method::pairing p,
                                                   const progress_fn& on_progress = {},
                                                   double angle_tolerance_deg = 0.0);

/// The cycles of rows from another source (a rig recording read back), with the same checks as
/// read_cycles; `path` names the source in messages. Rows must be valid recording rows.
[[nodiscard]] result<recording_cycles> cycles_of_rows(const std::string& path,
                                                      std::span<const method::row> rows,
                                                      method::pairing p,
                                                      std::vector<csv_metadata> metadata);

/// An encoder's angle (deg) as a position of the table: 0 within `tol` of 0 (or 360), 180 within
/// `tol` of 180, else nullopt.
[[nodiscard]] std::optional<double> position_of_angle(double angle_deg, double tol) noexcept;

/// A recording's columns held in memory (the Python module's arrays): one value per row;
/// `angle_deg` NaN while the table turns; `temp_c` and `n_avg` empty when absent.
struct recording_columns {
  std::span<const double> time_s, angle_deg, rate_dps, temp_c, n_avg;
};

/// Rows of columns in memory, with the checks of recording_reader. Errors name the column and
/// the 0-based row (`angle_deg[12]: ...`) or a column of the wrong length.
[[nodiscard]] result<std::vector<method::row>> rows_of_columns(const recording_columns& c,
                                                               double angle_tolerance_deg = 0.0);

}  // namespace gyroflip::io
