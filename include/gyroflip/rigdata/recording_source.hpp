/// \file
/// \brief Any recording as the method's row source (method/row_source.hpp): a `.gfr` rig
/// recording's dwells (`rig_rows`: positions from the device's step count, never an encoder) or
/// a CSV recording (io::recording_reader, encoder angles within a tolerance), chosen by name.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/method/row_source.hpp"
#include "gyroflip/rigdata/rig_run.hpp"

namespace gyroflip::rigdata {

/// A rig run's dwells as rows (dwell_row: one per dwell with conversions at a position of its
/// table, positions_of), with the run's metadata (csv_metadata) and the reader's warnings.
class rig_rows final : public method::row_source {
 public:
  explicit rig_rows(rig_run run);
  [[nodiscard]] result<std::size_t> read(std::span<method::row> out) override;
  [[nodiscard]] const std::string& name() const noexcept override { return run_.path; }
  [[nodiscard]] const position_table& positions() const noexcept override { return table_; }
  [[nodiscard]] bool has_temp() const noexcept override { return has_temp_; }
  [[nodiscard]] std::span<const metadata_entry> metadata() const noexcept override {
    return metadata_;
  }
  [[nodiscard]] std::span<const std::string> warnings() const noexcept override {
    return run_.warnings;
  }
  [[nodiscard]] std::uint64_t done() const noexcept override { return next_; }
  [[nodiscard]] std::uint64_t total() const noexcept override { return run_.dwells.size(); }

 private:
  rig_run run_;
  position_table table_;
  std::vector<metadata_entry> metadata_;
  std::size_t next_ = 0;  // the next dwell
  bool has_temp_ = false;
};

/// Opens a recording as rows: a `.gfr` (by its name) as rig_rows, any other file as a CSV
/// recording (io::recording_reader, `angle_tolerance_deg` for an encoder's angles; the `.gfr`'s
/// positions are the device's, so it does not apply there). Errors: those of the readers.
[[nodiscard]] result<std::unique_ptr<method::row_source>> open_recording(
    const std::string& path, double angle_tolerance_deg = 0.0);

/// The rows of a recording (open_recording) read whole, with its table, its metadata and the
/// reader's warnings. Used by the report and the Python module.
struct recording_rows {
  std::vector<method::row> rows;
  position_table positions;
  std::vector<io::csv_metadata> metadata;
  std::vector<std::string> warnings;
};
[[nodiscard]] result<recording_rows> read_recording_rows(const std::string& path,
                                                         double angle_tolerance_deg = 0.0);

}  // namespace gyroflip::rigdata
