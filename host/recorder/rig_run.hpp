/// \file
/// \brief A `.gfr` recording read back as a rig run (docs/FORMATS.md, "Rig recording"): the
/// device's dwells (and RAW conversions) in physical units, with the host's metadata and what the
/// link lost. The input of `export` and of `calibrate`, `compensate`, `adev`, `noise` on a `.gfr`.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "firmware/protocol/messages.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/method/types.hpp"
#include "host/recorder/gfr.hpp"

namespace gyroflip::host {

/// How device units become physical ones; stored in the recording's META record.
struct device_units {
  std::string sensor;                   ///< the sensor's preset name or file, as given
  double scale_factor_v_per_dps = 0.0;  ///< gyro output per deg/s (nominal, the preset's)
  /// Temperature channel: volts per degC and the temperature at 0 V differential (the rig's
  /// ADXRS150-class TEMP output read against the 2.5 V reference: 8.4 mV/K, 298 K at 2.5 V;
  /// docs/FACTS.md section 9).
  double temp_v_per_c = 8.4e-3;
  double temp_at_0v_c = 24.85;
};

/// Volts per code of the AD7739 at INFO's range code (data sheet: bipolar span 2 x full scale
/// over 2^24 codes; firmware/drivers/ad7739/convert.hpp).
[[nodiscard]] double adc_lsb_v(std::uint8_t range_code) noexcept;

/// One DWELL as recorded, with its time and physical values.
struct rig_dwell {
  protocol::dwell_msg d;
  std::uint16_t seq = 0;
  std::uint32_t segment = 0;  ///< which run of the device (a new one after each START)
  double time_s = 0.0;        ///< middle of the dwell: device clock, continued across segments
  double angle_deg = 0.0;     ///< 0 at position A, 180 at B
  double rate_dps = 0.0;      ///< mean gyro code x LSB / scale factor (NaN when n = 0)
  double temp_c = method::no_value;     ///< NaN without temperature conversions
  double accel_x_g = method::no_value;  ///< NaN when no PWM period was captured
  double accel_y_g = method::no_value;
};

/// One RAW conversion placed in its dwell.
struct rig_conversion {
  double time_s = 0.0;
  double angle_deg = 0.0;
  double rate_dps = 0.0;
  std::int32_t code = 0;
};

struct rig_run {
  std::string path;
  std::string meta_json;  ///< the META record as written
  device_units units;
  protocol::info_msg info;         ///< the last INFO of the device
  protocol::configure_msg config;  ///< the last configuration the device acknowledged
  std::vector<rig_dwell> dwells;
  std::vector<rig_conversion> conversions;  ///< only when asked for
  std::size_t frames = 0;                   ///< valid frames stored
  std::uint64_t corrupt_frames = 0;         ///< sum of the corrupt gap records
  std::uint64_t missing_frames = 0;         ///< sum of the missing gap records
  std::size_t device_resets = 0;
  std::size_t link_losses = 0;
  std::size_t unplaced_conversions = 0;  ///< RAW codes whose DWELL was lost (not in conversions)
  std::optional<gfr::stop_reason> stop;  ///< empty: the recorder did not end the file itself
  std::vector<std::string> warnings;     ///< `FILE: ...` for the caller to show
};

/// Builds a rig run record by record: the reader's and the live recorder's one interpretation.
class rig_run_builder {
 public:
  /// `with_conversions`: place every RAW code too. The first record must be META.
  rig_run_builder(std::string path, bool with_conversions);
  /// Takes record `n` (1-based, for messages). Errors: `FILE: record N: what`.
  [[nodiscard]] status add(const gfr::record& r, std::size_t n);
  /// The run so far.
  [[nodiscard]] const rig_run& run() const noexcept { return run_; }
  /// Ends the run: RAW codes still waiting for their DWELL are counted as unplaced.
  [[nodiscard]] rig_run finish() &&;

 private:
  void new_segment();
  void flush_pending();
  [[nodiscard]] double seconds(std::int64_t ticks) const;
  void add_dwell(const protocol::dwell_msg& d, std::uint16_t seq, std::uint64_t host_us);
  void place(const rig_dwell& r, double t0_s, double t1_s);
  void add_raw(const protocol::raw_msg& m);
  [[nodiscard]] std::int64_t ticks(std::uint32_t t);

  rig_run run_;
  bool with_conversions_;
  bool have_meta_ = false;
  bool have_info_ = false;
  double lsb_v_ = 0.0;
  std::uint32_t segment_ = 0;
  bool in_segment_ = false;
  // Device ticks (u32, wrapping) continued into one 64-bit count per segment.
  bool clock_started_ = false;
  std::uint32_t clock_last_ = 0;
  std::int64_t clock_total_ = 0;
  bool have_origin_ = false;
  std::int64_t origin_ticks_ = 0;   // first dwell's start in this segment
  double offset_s_ = 0.0;           // time of origin_ticks_
  double last_time_s_ = 0.0;        // end of the last dwell
  std::uint64_t last_host_us_ = 0;  // host time of the last dwell
  // RAW codes of this segment by dwell index (index within the dwell, code), until its DWELL.
  std::map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::int32_t>>> pending_;
};

/// Reads a `.gfr` recording; `with_conversions` places every RAW code too.
[[nodiscard]] result<rig_run> read_rig_run(const std::string& path, bool with_conversions = false);
/// The same from a parsed file.
[[nodiscard]] result<rig_run> interpret(const gfr::file& f, const std::string& path,
                                        bool with_conversions);
/// The META record's units (META is JSON: docs/FORMATS.md).
[[nodiscard]] result<device_units> units_of(const std::string& meta_json, const std::string& path);

/// A dwell as a recording row, unless it has no conversions or its table did not reach its
/// position (a step fault).
[[nodiscard]] std::optional<method::row> dwell_row(const rig_dwell& d);

/// The run's dwells as recording rows (docs/FORMATS.md): one per dwell with conversions whose
/// table reached its position (no step fault), `n_avg` = its conversions.
[[nodiscard]] std::vector<method::row> dwell_rows(const rig_run& run);

/// The `# key: value` metadata a recording CSV of this run carries (sensor, serial, ...).
[[nodiscard]] std::vector<io::csv_metadata> csv_metadata(const rig_run& run);

/// The rows of a recording: a `.gfr` rig recording's dwells (dwell_rows), or a CSV recording's
/// rows (io::recording_reader, encoder angles within `angle_tolerance_deg`), with its metadata
/// and the reader's warnings. Used by the CLI's report and the Python module.
struct recording_rows {
  std::vector<method::row> rows;
  std::vector<io::csv_metadata> metadata;
  std::vector<std::string> warnings;
};
[[nodiscard]] result<recording_rows> read_recording_rows(const std::string& path,
                                                         double angle_tolerance_deg = 0.0);

}  // namespace gyroflip::host
