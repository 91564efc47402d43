/// \file
/// \brief The crash-safe recorder (docs/RECORDER.md): talks to the rig over a serial port it
/// holds alone (handshake, CONFIGURE, START, STOP; every command carries an id and is retried
/// with it), stores every valid frame in a `.gfr` file as it arrives, asks the device to send
/// again what the line lost (RESEND) and records as a gap only what the device no longer has,
/// syncs the file at least once a second, follows a device reset (re-home, re-configure, resume)
/// and an unplugged adapter, refuses a different device, and reports progress through a
/// callback.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "firmware/protocol/messages.hpp"
#include "gyroflip/core/positions.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/method/stationarity.hpp"
#include "gyroflip/method/types.hpp"
#include "gyroflip/rig/rig_config.hpp"
#include "gyroflip/rigdata/gfr.hpp"
#include "gyroflip/rigdata/rig_run.hpp"

namespace gyroflip::host {

struct recorder_config {
  std::string port;  ///< serial device
  std::uint32_t baud = 115200;
  std::string output;               ///< the `.gfr` file (created; never replaced)
  double duration_s = 0.0;          ///< device-clock seconds to record (0: until stopped)
  rig::rig_config rig;              ///< what the device is configured with (checked first)
  rigdata::device_units units;      ///< stored in META for the reader
  rigdata::rig_mount_record mount;  ///< where the rig stands (META; unset parts not written)
  double reconnect_timeout_s = 60;  ///< how long a vanished port is waited for
  double reply_timeout_s = 2.0;     ///< how long a command's ACK (or INFO) is waited for
  /// How long the end of a run waits for frames still asked for again (RESEND).
  double drain_s = 2.0;
  /// The stationarity test run on the cycles as they arrive (method::check_stationarity, abba
  /// pairing): at 40 cycles, then at every 25 % more (method::next_stationarity_look), and at
  /// the end. None: not run.
  std::optional<method::stationarity_inputs> stationarity;
  // Host metadata for META.
  std::string software_version;
  std::vector<std::string> command_line;
};

/// What the recorder reports, about once a second of wall time.
struct recorder_status {
  double elapsed_s = 0.0;  ///< device clock since the first dwell
  double duration_s = 0.0;
  std::size_t dwells = 0;
  std::size_t cycles = 0;
  std::uint64_t frames_good = 0;       ///< valid frames received (retransmissions included)
  std::uint64_t frames_corrupt = 0;    ///< frames the line damaged (most come back: recovered)
  std::uint64_t frames_recovered = 0;  ///< frames received again after a RESEND
  std::uint64_t frames_lost = 0;       ///< frames the device no longer had: gap records
  /// Of the run's dwells, those missing from their runs (their index, n_positions x cycle +
  /// position, skipped; those before the first one seen included), as `export` counts them; while
  /// the run goes on, some may still come back on RESEND (frames_pending). The rest of
  /// frames_lost are STATUS frames and replies (the device keeps only data frames for RESEND), or
  /// frames after a run's last dwell (of any kind).
  std::uint64_t dwells_lost = 0;
  std::uint64_t frames_pending = 0;  ///< missing frames still asked for
  std::size_t device_resets = 0;
  std::size_t link_losses = 0;
  /// Running dN (live_pairing: abba over the table's 0/180 pair; for three or more positions the
  /// harmonic scheme's c1, as `calibrate --pairing harmonic` of the file; NaN before 3 cycles).
  double delta_n_dps = 0.0;
  double delta_n_se_dps = 0.0;  ///< its correlated standard error
  double temp_c = 0.0;          ///< last dwell's temperature (NaN without)
  std::uint64_t bytes = 0;      ///< of the file
  bool waiting_for_port = false;
  /// The board's serial (none before its INFO). 0 is an MSP430F149 whose information flash holds
  /// no serial record: it cannot be told from another board, so a lost line ends its recording.
  std::optional<std::uint32_t> serial;
  /// The last stationarity test of the cycles so far (none before the first, or when not asked).
  std::optional<method::stationarity> stationarity;
};

using recorder_progress_fn = std::function<void(const recorder_status&)>;

/// The scheme of the live cycles for the table a session configures (issue 33): abba over its
/// 0/180 pair for two positions (a table without one gives no live cycles), the harmonic scheme
/// (one estimate per visiting period, r = c1) for three or more. The caller's stationarity inputs
/// are this pairing's.
[[nodiscard]] method::pairing live_pairing(const position_table& table) noexcept;

struct recorder_result {
  recorder_status last;
  rigdata::gfr::stop_reason reason = rigdata::gfr::stop_reason::duration;
};

/// Records until `duration_s` of device time, `stop` turns true (the caller's signal handler), or
/// the port stays away longer than the reconnect timeout. The file is complete (STOP record,
/// synced) on every one of these ends. Errors before anything was recorded (no reply, another
/// protocol version, a refused configuration, a port another program holds) remove the file;
/// later ones (the disk is full, another device answers after a reconnect) stop the device and
/// leave the file readable up to them.
[[nodiscard]] result<recorder_result> record(const recorder_config& cfg,
                                             const std::atomic<bool>& stop,
                                             const recorder_progress_fn& on_progress = {});

/// Why a device refused CONFIGURE `c` with NAK `reason`, in words, naming the limit the
/// configuration passed where the host knows it (the device reports no limits of its own in INFO:
/// docs/PROTOCOL.md): the top step rate of the board `device` names (an MSP430F149 board:
/// firmware/ports/msp430f149/limits.hpp, the image's own constant), and the slowest start rate
/// its 16-bit step timer times at its tick rate. Without `device`, the reason's name.
[[nodiscard]] std::string configure_refusal(const protocol::configure_msg& c,
                                            const protocol::info_msg* device, std::uint8_t reason);

}  // namespace gyroflip::host
