/// \file
/// \brief `.gfr` rig recordings as input of calibrate, compensate, adev and noise
/// (docs/FORMATS.md, "Rig recording"): the same cycles and series a CSV recording gives.
#pragma once

#include <string>
#include <vector>

#include "gyroflip/core/progress.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/series.hpp"
#include "gyroflip/method/cycles.hpp"

namespace gyroflip::app {

/// A `.gfr` file (by its extension).
[[nodiscard]] bool is_rig_recording(const std::string& path);

/// The cycles of a CSV recording or of a `.gfr` rig recording's dwells.
[[nodiscard]] result<method::recording_cycles> read_recording_cycles(
    const std::string& path, method::pairing p, const progress_fn& on_progress,
    double angle_tolerance_deg = 0.0);

/// A `.gfr` recording as a series: `rate_dps` the per-cycle half-difference r (the flip-
/// compensated rate up to the constant dN, which no deviation sees), `bias_dps` the per-cycle
/// half-sum (the sensor's bias), `dwell_dps` the dwell means as they are (they switch with the
/// angle). One sample per cycle (per dwell), on the cycles' own grid.
///
/// A dwell that never arrived (or has no value: no conversion, a step fault), and the time
/// between two runs of the device (a reset), are gaps on that grid, as a CSV's missing time
/// stamps are (docs/FORMATS.md, "Time stamps"): `gaps` error names the first and the ways on;
/// split analyses the longest gap-free stretch of cycles; `bridge` (GRADEV, `--kind gradev`) puts
/// every stretch on one grid with NaN for what is missing. Either says how much it split off or
/// bridged (a note). With `all_parts` (noise), split also gives every gap-free stretch that
/// holds a sample there, each a series of its own on the one grid: the note then says they are
/// pooled (the longest is still returned).
[[nodiscard]] result<io::series> read_rig_series(const std::string& path, const std::string& column,
                                                 io::gap_policy gaps = io::gap_policy::error,
                                                 bool bridge = false,
                                                 std::vector<io::series>* all_parts = nullptr);

}  // namespace gyroflip::app
