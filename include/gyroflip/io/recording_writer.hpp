/// \file
/// \brief Writer of recordings in the gyroflip CSV format (docs/FORMATS.md), the counterpart of
/// recording_reader (recording.hpp): `# key: value` metadata lines, the header
/// `time_s,angle_deg,rate_dps,temp_c,n_avg`, then one row per dwell or per conversion. Numbers
/// are written in the shortest form that reads back to the same double, so writing and reading
/// a recording is the identity (`RecordingWriter.RoundTrip`). Text only: where it goes (an
/// atomic file, stdout) is the caller's choice. Used by `gyroflip simulate`.
#pragma once

#include <span>
#include <string>

#include "gyroflip/io/csv.hpp"
#include "gyroflip/method/types.hpp"

namespace gyroflip::io {

/// Appends `# key: value` lines, in order. Control bytes (a newline in a file name) and invalid
/// UTF-8 are escaped (core/error.hpp `printable`), so a value can never break the format.
void append_metadata(std::string& out, std::span<const csv_metadata> metadata);

/// Appends the metadata lines and the header line to `out`.
void append_recording_header(std::string& out, std::span<const csv_metadata> metadata);

/// Appends one row, its angle that of its position in `table` (the table turning: an empty
/// field). The metadata should name the table (`# positions_deg:`, position_table::describe).
/// Precondition: the other fields are finite (the reader would refuse an empty `temp_c`).
void append_recording_row(std::string& out, const method::row& r, const position_table& table);

}  // namespace gyroflip::io
