/// \file
/// \brief The calibration file (`gyroflip calibrate -o CAL.json`, read by `compensate
/// --calibration`): the same JSON object that `calibrate --json` prints (docs/FORMATS.md).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "gyroflip/core/result.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/cycle_print.hpp"
#include "gyroflip/method/delta_n_model.hpp"
#include "gyroflip/method/harmonic.hpp"
#include "gyroflip/method/stationarity.hpp"

namespace gyroflip::io {

/// Geometry given to `calibrate` (both or neither).
struct calibration_geometry {
  double lat_deg = 0.0;
  earth::ned_vector axis;
};

/// Where one run of a calibration came from, as `calibrate` recorded it (schema 2; absent in
/// older files): the bytes it read and what the recording's metadata says made it.
struct run_source {
  std::string sha256;  ///< of the file's bytes, lowercase hex
  std::uint64_t size_bytes = 0;
  /// "simulated" (gyroflip simulate), "emulated" (a rig recording of gyroflip's emulator), "rig"
  /// (a rig recording of a board) or "unknown" (a CSV whose metadata names no maker).
  std::string origin;
  std::string origin_detail;  ///< the same in words (which simulation, which device)
  [[nodiscard]] bool simulated() const noexcept {
    return origin == "simulated" || origin == "emulated";
  }
};

/// One input file's calibration.
struct calibration_entry {
  std::string file;
  method::calibration cal;
  std::optional<run_source> source;
  /// The run's stationarity test (method/stationarity.hpp) as calibrate made it (schema 3);
  /// nullopt: not checked (a file written before the test existed).
  std::optional<method::stationarity> stationarity = std::nullopt;
  /// The run's cycle values as a print (method/cycle_print.hpp; `cycle_print`, written since
  /// the fifth review of issue 31, F5): a copy of the run is found by content. nullopt: older
  /// files (and runs too short to print).
  std::optional<method::cycle_print> print = std::nullopt;
};

/// Which sensor and rig a recording (or a calibration) belongs to, from the recordings' `# key:
/// value` metadata (`gyroflip simulate` writes them; a recorder writes `serial`).
struct sensor_record {
  /// `sensor_name` (a preset or a TOML preset's name) and `serial` when given, else "unknown".
  std::string sensor = "unknown";
  /// The rig settings that change dN or its noise: n_avg, settle_s, positions_deg, flip,
  /// filter_word, chop, steps_per_rev, step_rate_sps, latitude_deg, axis - those present.
  std::vector<csv_metadata> rig;
  [[nodiscard]] bool known() const noexcept { return sensor != "unknown"; }
};

/// The sensor record of a recording's metadata.
[[nodiscard]] sensor_record sensor_of(std::span<const csv_metadata> metadata);

/// The rig settings in which `b` differs from `a` ("n_avg 256 vs 128", ...; a setting one side
/// lacks is not a difference).
[[nodiscard]] std::vector<std::string> rig_differences(const sensor_record& a,
                                                       const sensor_record& b);

/// What a user quotes from a calibration (workflow::budget_of's numbers, schema 3; absent in
/// older files): +- are 68.3 % intervals (Student's t for few runs).
struct calibration_uncertainty {
  double calibrated_dps = 0.0;     ///< how well the calibrated dN (mean or dN(T)) is known
  double repeatability_dps = 0.0;  ///< one power-up to the next (std; NaN: unknown)
  bool repeatability_measured = false;
  std::string repeatability_source;
  double between_run_dps = 0.0;   ///< random effects' tau (NaN: not estimated)
  double new_power_up_dps = 0.0;  ///< what a compensated rate carries (NaN: unknown)
  double coverage_factor = 1.0;   ///< Student's t applied
  std::size_t dof = 0;
};

/// Everything a calibration run produced.
struct calibration_record {
  /// The sensor and rig of the calibration's recordings; nullopt for files written before
  /// gyroflip recorded it.
  std::optional<sensor_record> sensor;
  method::pairing pairing = method::pairing::abba;
  method::calibration pooled;  ///< all cycles of all files together
  std::optional<calibration_geometry> geometry;
  std::vector<calibration_entry> files;
  std::optional<method::delta_n_model> model;          ///< dN(T), when several files were given
  std::optional<calibration_uncertainty> uncertainty;  ///< written by calibrate (schema 3)
  /// dN as named terms (schema 4; method::delta_n_term): empty when made in memory (written as
  /// the scheme's terms of `pooled`, method::terms_of); read from a file, its `terms`, or for a
  /// file before schema 4 the 0/180 schemes' one term, its pooled dN.
  std::vector<method::delta_n_term> terms;
  /// The terms' covariance ((deg/s)^2, row-major, terms.size()^2) when the scheme estimates
  /// several at once (harmonic: schema 4's `terms_covariance`); empty otherwise.
  std::vector<double> terms_covariance;
  /// What the terms hold and which pairs no run separates (harmonic: schema 4's
  /// `separability`; method::separability_of).
  std::optional<method::separability> separability;
};

/// A run's stationarity test as a calibration's `files[].stationarity` holds it (docs/FORMATS.md):
/// each statistic beside its limit and verdict; `{"checked": false, "why_not"}` when not checked.
/// Also reproduce's summary.json, for each simulated run.
[[nodiscard]] nlohmann::json stationarity_to_json(const method::stationarity& st);

/// A separability report as one JSON object (schema gyroflip.separability/1; `file` the
/// recording it is of, or empty for a table given before a run): the object a calibration's
/// `separability` holds (docs/FORMATS.md), with `schema`, `version` and `file`.
[[nodiscard]] std::string separability_to_json(const method::separability& s,
                                               const std::string& file);

/// The terms of dN a calibration states: `rec.terms`, or when empty its scheme's terms of its
/// pooled calibration (method::terms_of).
[[nodiscard]] std::vector<method::delta_n_term> terms_of(const calibration_record& rec);

/// The dN a calibration subtracts: its dN(T) model when it has one, else its pooled dN as a
/// constant (with the pooled correlated standard error).
[[nodiscard]] method::delta_n_model delta_n_model_of(const calibration_record& rec);

/// JSON text of a calibration (one line, keys as in docs/FORMATS.md; schema
/// gyroflip.calibration/5 and gyroflip's version, io/schema.hpp).
[[nodiscard]] result<std::string> to_json(const calibration_record& rec);

/// Reads a calibration file (schema 1 to 4): its pooled dN, its terms (schema 4; before, the one
/// term delta_n),, sensor, rig, pairing, model and the
/// runs it was made of (`files`: dN, correlated error, temperature, cycles, and from schema 2
/// each run's SHA-256, size and origin). Errors name the file (and the key that
/// is wrong).
[[nodiscard]] result<calibration_record> read_calibration_file(const std::string& path);
/// The same from the file's text (`path` names it in messages).
[[nodiscard]] result<calibration_record> parse_calibration(std::string_view text,
                                                           const std::string& path);

}  // namespace gyroflip::io
