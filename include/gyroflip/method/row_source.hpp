/// \file
/// \brief Where the method's rows come from: one interface that every reader of recordings
/// implements (a CSV recording streamed by io::recording_reader, a `.gfr` rig recording's dwells
/// by rigdata, rows already in memory by `rows_in_memory`), so that the pairing pipeline
/// (method/cycles.hpp) has one input and knows no file format.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gyroflip/core/metadata.hpp"
#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::method {

/// A stream of validated recording rows (time non-decreasing, position an index of the source's
/// table or table_moving while it turns, finite values, n_avg >= 1).
class row_source {
 public:
  row_source() = default;
  row_source(const row_source&) = default;
  row_source(row_source&&) = default;
  row_source& operator=(const row_source&) = default;
  row_source& operator=(row_source&&) = default;
  virtual ~row_source() = default;

  /// Fills the front of `out` with the next rows and returns how many (0: end of data; fewer
  /// than out.size() does not mean the end). Errors name the file, line and column (or record).
  [[nodiscard]] virtual result<std::size_t> read(std::span<row> out) = 0;
  /// The source's name in messages (a path, `<stdin>`, `<arrays>`).
  [[nodiscard]] virtual const std::string& name() const noexcept = 0;
  /// The table whose positions its rows name, known before the first row is read.
  [[nodiscard]] virtual const position_table& positions() const noexcept = 0;
  /// Whether its rows carry temperatures.
  [[nodiscard]] virtual bool has_temp() const noexcept = 0;
  /// Its `# key: value` metadata.
  [[nodiscard]] virtual std::span<const metadata_entry> metadata() const noexcept = 0;
  /// What the reader noticed without refusing the data (`FILE:LINE: what`), so far.
  [[nodiscard]] virtual std::span<const std::string> warnings() const noexcept = 0;
  /// Work done and its total for progress reports (bytes of a file, rows in memory; a total of 0
  /// is unknown, such as a pipe).
  [[nodiscard]] virtual std::uint64_t done() const noexcept = 0;
  [[nodiscard]] virtual std::uint64_t total() const noexcept = 0;
};

/// Rows held in memory (a simulation, a Python array, a rig run's dwells) as a row source, with
/// their table (default: the paper's 0/180). `has_temp` is true when there are rows and every one
/// has a temperature.
class rows_in_memory final : public row_source {
 public:
  rows_in_memory(std::string name, std::span<const row> rows,
                 std::vector<metadata_entry> metadata = {}, std::vector<std::string> warnings = {},
                 position_table positions = position_table::pair_0_180());
  [[nodiscard]] result<std::size_t> read(std::span<row> out) override;
  [[nodiscard]] const std::string& name() const noexcept override { return name_; }
  [[nodiscard]] const position_table& positions() const noexcept override { return positions_; }
  [[nodiscard]] bool has_temp() const noexcept override { return has_temp_; }
  [[nodiscard]] std::span<const metadata_entry> metadata() const noexcept override {
    return metadata_;
  }
  [[nodiscard]] std::span<const std::string> warnings() const noexcept override {
    return warnings_;
  }
  [[nodiscard]] std::uint64_t done() const noexcept override { return next_; }
  [[nodiscard]] std::uint64_t total() const noexcept override { return rows_.size(); }

 private:
  std::string name_;
  std::span<const row> rows_;
  std::vector<metadata_entry> metadata_;
  std::vector<std::string> warnings_;
  position_table positions_;
  std::size_t next_ = 0;
  bool has_temp_ = false;
};

}  // namespace gyroflip::method
