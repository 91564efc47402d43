/// \file
/// \brief Reader of recordings in the gyroflip CSV format (docs/FORMATS.md): validated rows, as
/// a method::row_source (the pairing pipeline, method/cycles.hpp, reads them).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/method/row_source.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::io {

/// Where a recording's table comes from (docs/FORMATS.md, "Positions"):
/// - `line`: its `# positions_deg: A,B,...` line (1 to 8 distinct angles in [0, 360); index i is
///   the i-th angle);
/// - `rows`: `# positions_deg: auto`, the distinct angles of its rows, ascending (a first pass over
///   the file's angle column; not standard input, which cannot be read twice; angles as written,
///   so not with an angle tolerance);
/// - `pair_0_180`: no such line, the paper's 0 and 180 deg: every recording before the table line
///   reads as it did (an encoder's angles within the tolerance of 0 or 180 read as those; any
///   other angle is refused at its line and column).
/// The one place a recording's angles are checked against its table (the CSV reader and
/// rows_of_columns); errors name the file, line and column (or the array and row).
enum class table_origin { line, rows, pair_0_180 };

/// Streams the rows of a recording, checking each one: `time_s` finite and non-decreasing,
/// `angle_deg` a position of the recording's table (table_origin; within a tolerance; empty =
/// table turning), `rate_dps` finite, `temp_c` finite when the column exists, `n_avg` a whole
/// number >= 1 (default 1). Each row carries its position's index.
class recording_reader final : public method::row_source {
 public:
  /// Temperatures a recording may hold (degC): absolute zero to 1000 degC.
  static constexpr double min_temp_c = -273.15;
  static constexpr double max_temp_c = 1000.0;

  /// Largest `angle_tolerance_deg` (deg): an encoder angle further than this from its position
  /// is a table that did not reach it.
  static constexpr double max_angle_tolerance_deg = 10.0;

  /// `angle_tolerance_deg` in [0, max_angle_tolerance_deg]: an angle within it of a position of
  /// the table (on the circle: 359.8 is 0.2 from 0) reads as that position (an encoder's
  /// reading). Errors: the file's, a bad `# positions_deg:` line (its line and column), more
  /// than 8 distinct angles (the row and column of the ninth).
  [[nodiscard]] static result<recording_reader> open(const std::string& path,
                                                     double angle_tolerance_deg = 0.0);

  /// Reads the next row into `out`. `failed` -> `last_error()` has FILE:LINE:COL.
  [[nodiscard]] csv_reader::step next(method::row& out);
  [[nodiscard]] const error& last_error() const noexcept { return error_; }

  // method::row_source: the next rows (next() a block at a time), the file's path, whether it
  // has a temp_c column, its `# key: value` lines, warnings about rows read (`FILE:LINE: what`,
  // e.g. a last line without newline), bytes read of the file's size.
  [[nodiscard]] result<std::size_t> read(std::span<method::row> out) override;
  [[nodiscard]] const std::string& name() const noexcept override { return csv_.path(); }
  [[nodiscard]] const position_table& positions() const noexcept override { return table_; }
  [[nodiscard]] table_origin origin() const noexcept { return origin_; }
  [[nodiscard]] bool has_temp() const noexcept override { return has_temp_; }
  [[nodiscard]] std::span<const csv_metadata> metadata() const noexcept override {
    return csv_.metadata();
  }
  [[nodiscard]] std::span<const std::string> warnings() const noexcept override {
    return warnings_;
  }
  [[nodiscard]] std::uint64_t done() const noexcept override { return csv_.bytes_done(); }
  [[nodiscard]] std::uint64_t total() const noexcept override { return csv_.bytes_total(); }
  [[nodiscard]] const std::string& path() const noexcept { return csv_.path(); }

 private:
  // cppcheck-suppress passedByValue ; sink parameter, moved from
  explicit recording_reader(csv_reader c) noexcept : csv_(std::move(c)) {}
  csv_reader::step fail(const error& e);
  // A row through csv_reader's fast path when it and every check take it (false: next()'s
  // general path reads the row and says what is wrong with it).
  bool next_plain(method::row& out);
  csv_reader csv_;
  bool has_temp_ = false;
  bool has_n_avg_ = false;
  double angle_tolerance_deg_ = 0.0;
  position_table table_;
  table_origin origin_ = table_origin::pair_0_180;
  int at_0_ = table_moving, at_180_ = table_moving;  // the positions `0` and `180` read as
  double last_time_s_ = -1e300;
  std::size_t last_time_line_ = 0;
  error error_{errc::bad_input, {}};
  std::vector<std::string> warnings_;
};

/// A recording's columns held in memory (the Python module's arrays): one value per row;
/// `angle_deg` NaN while the table turns; `temp_c` and `n_avg` empty when absent;
/// `positions_deg` the table (empty: the paper's 0 and 180, as a CSV without its table line).
struct recording_columns {
  std::span<const double> time_s, angle_deg, rate_dps, temp_c, n_avg;
  std::span<const double> positions_deg{};  // may be left out of an initializer
};

/// Rows with the table whose positions they name.
struct table_rows {
  std::vector<method::row> rows;
  position_table positions;
};

/// Rows of columns in memory, with the checks of recording_reader. Errors name the column and
/// the 0-based row (`angle_deg[12]: ...`) or a column of the wrong length.
[[nodiscard]] result<table_rows> rows_of_columns(const recording_columns& c,
                                                 double angle_tolerance_deg = 0.0);

}  // namespace gyroflip::io
