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
/// into the angle table of the CONFIGURE in force, never guessed. Device time is unwrapped into
/// 64 bits (days at any tick rate). What cannot be established - which board sent a frame (a
/// reconnected line before the device was identified, another serial, a STATUS of another boot
/// with no reset recorded), which boot (damage between two of them), which configuration - is
/// never guessed: those dwells are counted and left out, with a warning each (docs/FORMATS.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
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
  /// The sensor model's parameters (sensor::fields() keys and values; META's `sensor_params`,
  /// written by `record` since issue 31): a recording carries the model --sensor named, so its
  /// g-sensitivity specification goes with it as a simulated run's `# sensor.*` header does
  /// (workflow::resolve_sensor_spec). Empty in files recorded before.
  std::vector<std::pair<std::string, double>> sensor_params;
};

/// Where the rig stood, as `record --table-axis/--azimuth` stored it in META (issue 33): the
/// table's axis (`up`, `down`, a name or N,E,D, as simulate's `--table-axis`) and the azimuth
/// (deg from north, clockwise) of the sensitive axis at the table's 0 deg. Empty / unset: not
/// recorded (a recording made before gyroflip stored them, or without the options); the reader
/// then writes no `# table_axis:` / `# azimuth_deg:` and `heading` and `calibrate` say so.
struct rig_mount_record {
  std::string table_axis;
  std::optional<double> azimuth_deg;
};

/// The mount META holds (its `table_axis` and `azimuth_deg` keys; absent, null or of another type:
/// not recorded). An azimuth outside [-360, 360] or not finite is not recorded either.
[[nodiscard]] rig_mount_record mount_of_meta(const std::string& meta_json);

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
  std::size_t record = 0;     ///< the FRAME record it was read from (its number in the file)
  /// Its place in its run: n_positions x cycle + position (a missing index: a lost dwell).
  std::uint64_t index = 0;
  double time_s = 0.0;     ///< middle of the dwell: device clock, continued across segments
  double angle_deg = 0.0;  ///< the angle table's angle of its position
  double rate_dps = 0.0;   ///< mean gyro code x LSB / scale factor (NaN when n = 0)
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
  rig_mount_record mount;                   ///< where the rig stood (META; may be unrecorded)
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
  /// DWELLs of a board not identified: stored after the port was lost and before the recorder
  /// knew the device again (a reconnect), or after a STATUS of another boot with no reset
  /// recorded (another board, or a reset the recorder did not see): not used.
  std::size_t unidentified = 0;
  std::size_t other_board = 0;  ///< DWELLs after an INFO of another serial: not used
  /// DWELLs whose device boot cannot be established (stored between two damaged regions, one of
  /// which held the reset), or whose device times go backwards within their run: not used.
  std::size_t unknown_boot = 0;
  /// DWELLs with no intact INFO in the file to convert them (tick rate, ADC range): not used.
  std::size_t unconverted = 0;
  std::size_t damaged_regions = 0;   ///< regions of the file no record could be read from
  std::size_t repaired_records = 0;  ///< records with one flipped bit put right (CRC-32)
  std::size_t restored_records = 0;  ///< damaged records put back from their COPY
  std::size_t inferred_resets = 0;   ///< device resets whose GAP record was lost in damage
  std::size_t rebuilt_starts = 0;    ///< START records lost in damage, rebuilt from their ACK
  /// DWELLs of a run whose START record is not in the file (cut off before it was written),
  /// labelled by the CONFIGURE their boot acknowledged before them: a device starts only with the
  /// configuration in force, and only a CONFIGURE it acknowledges changes it (docs/PROTOCOL.md).
  std::size_t by_configure = 0;
  /// How far the time_s of a run after the first may be off, s: such a run is placed after the
  /// run before it by the host's clock (no earlier than its boot's own clock says it ran before
  /// its first dwell), which stands in for the device's only at the same pace (0: they kept it;
  /// an emulator run S times fast leaves later runs early by about the gap times S - 1, with a
  /// warning naming the run: an estimate at the last run's pace).
  double later_runs_shift_s = 0.0;
  /// A run after the first was placed by the host's clock while the device's kept another pace
  /// (beyond 1 %, or a shift beyond 1 s): warned about, naming the run; later_runs_shift_s is
  /// then an estimate at the last run's pace, not a bound (issue 32).
  bool later_runs_off_pace = false;
  std::optional<gfr::stop_reason> stop;  ///< empty: the recorder did not end the file itself
  std::vector<std::string> warnings;     ///< `FILE: ...` for the caller to show
};

/// Builds a rig run record by record: the reader's and the live recorder's one interpretation.
/// While records come in, run() holds the dwells in arrival order (a live view); finish() puts
/// them in order, places each in its device boot and run, and checks them.
class rig_run_builder {
 public:
  /// `with_conversions`: place every RAW code too. The first record must be META.
  rig_run_builder(std::string path, bool with_conversions);
  /// Takes record `n` (its number in the file, for messages). Errors: `FILE: record N: what`.
  [[nodiscard]] status add(const gfr::record& r, std::size_t n);
  /// Bytes of the file before the next record were damaged beyond reading (gfr::file::damaged):
  /// what lies on either side of them may belong to different device boots.
  void add_damage(const gfr::damaged_region& d);
  /// The run so far.
  [[nodiscard]] const rig_run& run() const noexcept { return run_; }
  /// Ends the run: dwells ordered and timed, RAW codes placed, lost dwells counted, what cannot
  /// be placed counted and left out. Errors: a dwell's temperature outside what a recording may
  /// hold.
  [[nodiscard]] result<rig_run> finish() &&;

 private:
  // What a record said, in file order, for finish().
  enum class ev : std::uint8_t {
    info,
    configure,
    start,
    dwell,
    raw,
    status,
    ack_start,
    ack_configure,
    other,
    gap_reset,
    gap_link,
    damage
  };
  struct event {
    ev type = ev::other;
    std::size_t record = 0;
    std::uint64_t host_us = 0;
    std::uint16_t seq16 = 0;  // a frame's sequence number; a START's ACK number (has_seq)
    bool has_seq = false;
    std::uint32_t index = 0;  // into the vector of its type; a link GAP: its milliseconds
  };
  struct status_seen {
    std::uint16_t boot = 0;
    std::uint32_t uptime_ticks = 0;
  };
  struct start_seen {
    std::optional<std::uint16_t> crc;  // the configuration's CRC (format 3)
    std::size_t config_event = 0;      // the CONFIGURE or INFO event in force (npos: none)
  };

  [[nodiscard]] rig_dwell physical(const protocol::dwell_msg& d, const protocol::configure_msg& c,
                                   double lsb_v, double t0_s, double t1_s) const;

  rig_run run_;
  bool with_conversions_;
  bool have_meta_ = false;
  bool have_info_ = false;
  double lsb_v_ = 0.0;
  std::size_t config_event_ = static_cast<std::size_t>(-1);
  std::vector<event> events_;
  std::vector<protocol::info_msg> infos_;
  std::vector<protocol::configure_msg> configs_;
  std::vector<start_seen> starts_;
  std::vector<protocol::dwell_msg> dwell_msgs_;
  std::vector<protocol::raw_msg> raws_;
  std::vector<status_seen> statuses_;
  std::vector<std::uint16_t> ack_at_;
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

/// The run's table of positions: its configuration's angle table (table_of_configure).
[[nodiscard]] position_table positions_of(const rig_run& run);
/// A configuration's angle table as a position table (position_table::of_visits: each angle
/// once, with the steps of its first position); empty if it is not a valid table.
[[nodiscard]] position_table table_of_configure(const protocol::configure_msg& c);

/// A dwell as a recording row at its position of `table` (found by its angle), unless it has no
/// conversions, its table did not reach its position (a step fault), or its angle is not one of
/// `table`'s (a run of another configuration).
[[nodiscard]] std::optional<method::row> dwell_row(const rig_dwell& d, const position_table& table);

/// The run's dwells as recording rows (docs/FORMATS.md) at the positions of positions_of(run):
/// one per dwell that dwell_row takes, `n_avg` = its conversions.
[[nodiscard]] std::vector<method::row> dwell_rows(const rig_run& run);

/// The `# key: value` metadata a recording CSV of this run carries (sensor, serial, ...).
[[nodiscard]] std::vector<io::csv_metadata> csv_metadata(const rig_run& run);

/// The part of csv_metadata that names the sensor: `sensor_name` and one `sensor.KEY` per
/// recorded parameter (device_units::sensor_params). `record` resolves its live stationarity
/// test's specification from these before the file exists, as calibrate does from the file.
[[nodiscard]] std::vector<io::csv_metadata> sensor_metadata(const device_units& units);

}  // namespace gyroflip::rigdata
