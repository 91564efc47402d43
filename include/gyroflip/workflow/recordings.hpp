/// \file
/// \brief Any recording as the method's input (module workflow): a CSV recording
/// (docs/FORMATS.md; streamed) or a `.gfr` rig recording (rigdata, its dwells), as cycles for
/// calibrate and compensate, or as a whole run (rows, dwells, both pairings) for the report.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/cycles.hpp"
#include "gyroflip/method/types.hpp"
#include "gyroflip/report/page.hpp"

namespace gyroflip::workflow {

/// The cycles of a recording with pairing `p` (method::read_cycles on rigdata::open_recording):
/// a CSV recording read in one streamed pass (`on_progress` in bytes), or a `.gfr` rig
/// recording's dwells (positions from the device's step count, so the angle tolerance does not
/// apply). The reader's warnings (a damaged region skipped) are in `warnings`. Errors: those of
/// the readers, fewer than method::min_cycles cycles.
[[nodiscard]] result<method::recording_cycles> read_cycles(const std::string& path,
                                                           method::pairing p,
                                                           const progress_fn& on_progress = {},
                                                           double angle_tolerance_deg = 0.0);

/// One recording read whole: its dwells and its cycles by both pairings (paper eqn 7 and abba).
struct recording_run {
  std::string file;
  std::vector<io::csv_metadata> metadata;
  std::vector<std::string> warnings;
  position_table positions = position_table::pair_0_180();  ///< the recording's table
  method::flip_pair pair;             ///< the pairings' two positions (method/flip_pair.hpp)
  std::vector<method::dwell> dwells;  ///< the dwells at the pair's positions
  std::vector<method::cycle> simple, abba;
  bool has_temp = false;
  /// The time one conversion takes: the median spacing of consecutive rows of a dwell per
  /// conversion they average (s; 0 when no dwell has two rows). A dwell's data span its weight
  /// times this; the rest of the cycle is turning and settling (the dead time).
  double conversion_s = 0.0;
  /// The cycles of pairing `p`.
  [[nodiscard]] const std::vector<method::cycle>& cycles(method::pairing p) const noexcept {
    return p == method::pairing::abba ? abba : simple;
  }
};

/// The value of metadata key `key` (`# key: value`), empty when the recording has none.
[[nodiscard]] std::string metadata_value(std::span<const io::csv_metadata> metadata,
                                         std::string_view key);

/// Where a recording came from, from its name and metadata (docs/REPORT.md, "Provenance"):
/// `simulated` (a `# gyroflip simulate` line), `emulated` (a rig recording whose INFO names
/// gyroflip's emulator), `rig` (any other `.gfr`) or `unknown` (a CSV naming no maker), with
/// its detail in words; the SHA-256 and size are left empty.
[[nodiscard]] io::run_source origin_of(const std::string& file,
                                       std::span<const io::csv_metadata> metadata);

/// A recording's source as a calibration keeps it: origin_of, with the SHA-256 and size of its
/// bytes as report::identify_file found them.
[[nodiscard]] io::run_source source_of(const std::string& file,
                                       std::span<const io::csv_metadata> metadata,
                                       const report::input_file& bytes);

/// Why two runs are one recording: the same bytes (both sources name one SHA-256: a copy under
/// another name, which io::check_distinct_inputs does not see), or the same cycles (dN, std and
/// count equal to the last bit: a `.gfr` and its CSV export, a copy with another newline).
enum class repeat { none, same_bytes, same_cycles };
[[nodiscard]] repeat repeat_of(const io::calibration_entry& a, const io::calibration_entry& b);

/// Refuses runs among which one recording comes twice (repeat_of): not two power-ups. Errors
/// name both files.
[[nodiscard]] status check_distinct_runs(std::span<const io::calibration_entry> runs);

/// The runs' calibrations, for the method's statistics over runs (method/runs.hpp).
[[nodiscard]] std::vector<method::calibration> calibrations_of(
    std::span<const io::calibration_entry> runs);

/// The origin as a page says it ("simulated: gyroflip simulate (...)").
[[nodiscard]] std::string origin_words(const io::run_source& src);

/// Reads a recording (CSV or `.gfr`) whole. Errors: those of the readers and of
/// method::cycles_of_rows.
[[nodiscard]] result<recording_run> read_run(const std::string& path,
                                             double angle_tolerance_deg = 0.0);

/// The same from rows already in memory (a simulation); `name` names them in messages.
[[nodiscard]] result<recording_run> run_of_rows(
    const std::string& name, std::vector<method::row> rows, std::vector<io::csv_metadata> metadata,
    const position_table& positions = position_table::pair_0_180());

}  // namespace gyroflip::workflow
