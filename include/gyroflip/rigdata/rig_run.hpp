/// \file
/// \brief A `.gfr` recording read back as a rig run (docs/FORMATS.md, "Rig recording"): the
/// device's dwells (and RAW conversions) in physical units, with the host's metadata and what the
/// link lost. The input of `export`, `report` and of `calibrate`, `compensate`, `adev`, `noise`
/// on a `.gfr`; part of the library (module rigdata) for find_package(gyroflip) users.
///
/// Frames are stored as they arrived, so a frame the device sent again (RESEND) may come after
/// later ones: the reader orders each run's dwells by their sequence numbers. A run (segment)
/// holds the device's frames after the ACK of its START (the START record names that frame), in
/// the device session (between two reboots) it was started in; a dwell's position is an index
/// into the angle table of the CONFIGURE in force, never guessed.
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
#include "gyroflip/rigdata/gfr.hpp"

namespace gyroflip::rigdata {

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

/// The bounds META's conversion must keep (the same as a recording CSV's temperatures:
/// io::recording_reader): |temp_v_per_c| in [1e-6, 10] V/degC, temp_at_0v_c in
/// [-273.15, 1000] degC, |scale_factor_v_per_dps| in [1e-6, 100] V/(deg/s).
[[nodiscard]] status check_units(const device_units& u, const std::string& what);

/// Volts per code of the AD7739 at INFO's range code (data sheet: bipolar span 2 x full scale
/// over 2^24 codes; firmware/drivers/ad7739/convert.hpp).
[[nodiscard]] double adc_lsb_v(std::uint8_t range_code) noexcept;

/// One DWELL as recorded, with its time and physical values.
struct rig_dwell {
  protocol::dwell_msg d;
  std::uint16_t seq = 0;
  std::uint32_t segment = 0;  ///< which run of the device (a new one after each START)
  double time_s = 0.0;        ///< middle of the dwell: device clock, continued across segments
  double angle_deg = 0.0;     ///< the angle table's angle of its position
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
  protocol::info_msg info;                  ///< the last INFO of the device
  protocol::configure_msg config;           ///< the last configuration the device acknowledged
  std::vector<rig_dwell> dwells;            ///< in order: by segment, then by sequence number
  std::vector<rig_conversion> conversions;  ///< only when asked for
  std::size_t frames = 0;                   ///< valid frames stored
  std::uint64_t corrupt_frames = 0;         ///< frames damaged on the line (most were sent again)
  std::uint64_t missing_frames = 0;  ///< frames lost for good (the device no longer had them)
  std::size_t lost_dwells = 0;       ///< dwells of each run that never arrived
  std::size_t device_resets = 0;
  std::size_t link_losses = 0;
  std::size_t unplaced_conversions = 0;  ///< RAW codes whose DWELL was lost (not in conversions)
  std::size_t outside_runs = 0;  ///< DWELLs of no acknowledged START (a run left from before)
  /// DWELLs of a run whose configuration is not in the file (its CONFIGURE record damaged):
  /// their angles are unknown, so they are not used.
  std::size_t unknown_config = 0;
  std::optional<gfr::stop_reason> stop;  ///< empty: the recorder did not end the file itself
  std::vector<std::string> warnings;     ///< `FILE: ...` for the caller to show
};

/// Builds a rig run record by record: the reader's and the live recorder's one interpretation.
/// While records come in, run() holds the dwells in arrival order (a live view); finish() puts
/// them in order and checks them.
class rig_run_builder {
 public:
  /// `with_conversions`: place every RAW code too. The first record must be META.
  rig_run_builder(std::string path, bool with_conversions);
  /// Takes record `n` (1-based, for messages). Errors: `FILE: record N: what`.
  [[nodiscard]] status add(const gfr::record& r, std::size_t n);
  /// The run so far.
  [[nodiscard]] const rig_run& run() const noexcept { return run_; }
  /// Ends the run: dwells ordered and timed, RAW codes placed, lost dwells counted. Errors:
  /// a dwell's temperature outside what a recording may hold, device times that go backwards.
  [[nodiscard]] result<rig_run> finish() &&;

 private:
  // A dwell as it arrived: its device session, sequence number (unwrapped) and record.
  struct arrival {
    protocol::dwell_msg d;
    std::uint32_t session = 0;
    std::uint64_t seq = 0;
    std::uint16_t seq16 = 0;
    std::size_t record = 0;
    std::uint64_t host_us = 0;
    protocol::configure_msg config;  // the configuration in force when it arrived
  };
  struct raw_block {
    protocol::raw_msg m;
    std::uint32_t session = 0;
    std::uint64_t seq = 0;
    std::size_t record = 0;
  };
  // A START: its session, the sequence number after which its frames begin (or the record
  // position, for a file of format 1), the configuration it started.
  struct start_mark {
    std::uint32_t session = 0;
    std::optional<std::uint64_t> after_seq;
    std::size_t record = 0;
    std::uint64_t host_us = 0;
    protocol::configure_msg config;
    bool config_known = true;  // the START's configuration CRC matches `config` (format 3)
  };

  [[nodiscard]] std::uint64_t unwrap(std::uint16_t seq);
  [[nodiscard]] double angle_of(const protocol::configure_msg& c, std::uint8_t pos) const;
  [[nodiscard]] rig_dwell physical(const protocol::dwell_msg& d, const protocol::configure_msg& c,
                                   double t0_s, double t1_s) const;
  void place(const rig_dwell& r, double t0_s, double t1_s,
             std::map<std::uint64_t, std::vector<std::pair<std::uint32_t, std::int32_t>>>& pend,
             const protocol::configure_msg& cfg);

  rig_run run_;
  bool with_conversions_;
  bool have_meta_ = false;
  bool have_info_ = false;
  double lsb_v_ = 0.0;
  std::uint32_t session_ = 0;
  bool have_seq_ = false;
  std::uint64_t highest_seq_ = 0;
  std::vector<arrival> arrivals_;
  std::vector<raw_block> raws_;
  std::vector<start_mark> starts_;
  // The live view's clock: device ticks continued in arrival order.
  std::uint32_t live_last_ = 0;
  bool live_started_ = false;
  double live_s_ = 0.0;
};

/// Reads a `.gfr` recording; `with_conversions` places every RAW code too; `strict` refuses a
/// damaged region in the middle instead of skipping it (gfr::read).
[[nodiscard]] result<rig_run> read_rig_run(const std::string& path, bool with_conversions = false,
                                           bool strict = false);
/// The same from a parsed file.
[[nodiscard]] result<rig_run> interpret(const gfr::file& f, const std::string& path,
                                        bool with_conversions);
/// The META record's units (META is JSON: docs/FORMATS.md), checked by check_units.
[[nodiscard]] result<device_units> units_of(const std::string& meta_json, const std::string& path);

/// A dwell as a recording row, unless it has no conversions, its table did not reach its
/// position (a step fault), or its position is not 0 or 180 deg (a recording's two positions).
[[nodiscard]] std::optional<method::row> dwell_row(const rig_dwell& d);

/// The run's dwells as recording rows (docs/FORMATS.md): one per dwell that dwell_row takes,
/// `n_avg` = its conversions.
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

}  // namespace gyroflip::rigdata
