/// \file
/// \brief Reader of recordings in the gyroflip CSV format (docs/FORMATS.md): validated rows, as
/// a method::row_source (the pairing pipeline, method/cycles.hpp, reads them).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/method/row_source.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::io {

/// Streams the rows of a recording, checking each one: `time_s` finite and non-decreasing,
/// `angle_deg` 0 or 180 (within a tolerance; empty = table turning), `rate_dps` finite, `temp_c`
/// finite when the column exists, `n_avg` a whole number >= 1 (default 1).
class recording_reader final : public method::row_source {
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

  // method::row_source: the next rows (next() a block at a time), the file's path, whether it
  // has a temp_c column, its `# key: value` lines, warnings about rows read (`FILE:LINE: what`,
  // e.g. a last line without newline), bytes read of the file's size.
  [[nodiscard]] result<std::size_t> read(std::span<method::row> out) override;
  [[nodiscard]] const std::string& name() const noexcept override { return csv_.path(); }
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
  csv_reader csv_;
  bool has_temp_ = false;
  bool has_n_avg_ = false;
  double angle_tolerance_deg_ = 0.0;
  double last_time_s_ = -1e300;
  std::size_t last_time_line_ = 0;
  error error_{errc::bad_input, {}};
  std::vector<std::string> warnings_;
};

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
