/// \file
/// \brief The crash-safe recorder (docs/RECORDER.md): talks to the rig over a serial port
/// (handshake, CONFIGURE, START, STOP), stores every valid frame in a `.gfr` file as it arrives,
/// syncs it at least once a second, records link faults as gap records, follows a device reset
/// and an unplugged adapter, and reports progress through a callback.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "firmware/protocol/messages.hpp"
#include "gyroflip/core/result.hpp"
#include "host/recorder/gfr.hpp"
#include "host/recorder/rig_run.hpp"

namespace gyroflip::host {

struct recorder_config {
  std::string port;  ///< serial device
  std::uint32_t baud = 115200;
  std::string output;               ///< the `.gfr` file (created; never replaced)
  double duration_s = 0.0;          ///< device-clock seconds to record (0: until stopped)
  protocol::configure_msg device;   ///< what the device is configured with
  device_units units;               ///< stored in META for the reader
  double reconnect_timeout_s = 60;  ///< how long a vanished port is waited for
  double reply_timeout_s = 2.0;     ///< how long a command's ACK (or INFO) is waited for
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
  std::uint64_t frames_good = 0;
  std::uint64_t frames_corrupt = 0;
  std::uint64_t frames_missing = 0;
  std::size_t device_resets = 0;
  std::size_t link_losses = 0;
  double delta_n_dps = 0.0;     ///< running dN (abba pairing; NaN before 3 cycles)
  double delta_n_se_dps = 0.0;  ///< its correlated standard error
  double temp_c = 0.0;          ///< last dwell's temperature (NaN without)
  std::uint64_t bytes = 0;      ///< of the file
  bool waiting_for_port = false;
};

using recorder_progress_fn = std::function<void(const recorder_status&)>;

struct recorder_result {
  recorder_status last;
  gfr::stop_reason reason = gfr::stop_reason::duration;
};

/// Records until `duration_s` of device time, `stop` turns true (the caller's signal handler), or
/// the port stays away longer than the reconnect timeout. The file is complete (STOP record,
/// synced) on every one of these ends. Errors before anything was recorded (no reply, another
/// protocol version, a refused configuration) remove the file; later ones leave it readable.
[[nodiscard]] result<recorder_result> record(const recorder_config& cfg,
                                             const std::atomic<bool>& stop,
                                             const recorder_progress_fn& on_progress = {});

}  // namespace gyroflip::host
