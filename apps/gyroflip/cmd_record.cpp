/// \file
/// \brief `gyroflip record` (docs/RECORDER.md): the recorder on a serial port, with a progress
/// line on a terminal or JSON lines for scripts, and Ctrl-C as a clean end.
#include "cmd_record.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/earth/earth.hpp"
#include "gyroflip/rigdata/rig_run.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "gyroflip/workflow/calibrate.hpp"
#include "host/recorder/recorder.hpp"
#include "stop_signal.hpp"

namespace gyroflip::app {

namespace {

result<rig::rig_config> device_config(const record_options& o) {
  auto r = rig_config_of(o.rig);
  if (!r) return r.err();
  r->raw = o.raw;
  // The visiting order is written into the angle table the device steps through.
  const auto order = o.order == "cycle"            ? rig::device_order::cycle
                     : o.order == "there-and-back" ? rig::device_order::there_and_back
                                                   : rig::device_order::automatic;
  auto visits = rig::device_visits(r->positions_deg, order, r->one_way);
  if (!visits) return visits.err();
  r->positions_deg = std::move(*visits);
  if (auto s = r->check(); !s) return s.err();
  return r;
}

std::string num(double v, const char* spec) {
  return std::isfinite(v) ? fmt::format(fmt::runtime(spec), v) : std::string("-");
}

// One line, redrawn in place on a terminal.
void draw(const host::recorder_status& s) {
  const std::string of = s.duration_s > 0 ? fmt::format("/{:.0f}", s.duration_s) : "";
  std::string line = fmt::format(
      "\r{:.0f}{} s  cycles {}  frames {} good {} resent  lost {} dwells {} other  dN {} +- {} "
      "deg/s  T {} C",
      s.elapsed_s, of, s.cycles, s.frames_good, s.frames_recovered, s.dwells_lost,
      s.frames_lost - std::min(s.frames_lost, s.dwells_lost), num(s.delta_n_dps, "{:.5e}"),
      num(s.delta_n_se_dps, "{:.1e}"), num(s.temp_c, "{:.2f}"));
  if (s.waiting_for_port) line += "  (waiting for the port)";
  std::fprintf(stderr, "%s\033[K", line.c_str());
  std::fflush(stderr);
}

// The live stationarity test as the progress lines carry it (null before its first look).
nlohmann::json stationarity_json(const std::optional<method::stationarity>& st) {
  if (!st) return nullptr;
  return {{"checked", st->checked},
          {"stationary", !st->failed()},
          {"summary", st->checked ? st->summary() : st->why_not}};
}

nlohmann::json json_of(const host::recorder_status& s) {
  const auto or_null = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; };
  return {{"elapsed_s", s.elapsed_s},
          {"duration_s", s.duration_s},
          {"dwells", s.dwells},
          {"cycles", s.cycles},
          {"frames_good", s.frames_good},
          {"frames_corrupt", s.frames_corrupt},
          {"frames_recovered", s.frames_recovered},
          {"frames_lost", s.frames_lost},
          {"dwells_lost", s.dwells_lost},
          {"frames_pending", s.frames_pending},
          {"device_resets", s.device_resets},
          {"link_losses", s.link_losses},
          {"delta_n_dps", or_null(s.delta_n_dps)},
          {"delta_n_se_dps", or_null(s.delta_n_se_dps)},
          {"temp_c", or_null(s.temp_c)},
          {"bytes", s.bytes},
          {"waiting_for_port", s.waiting_for_port},
          {"stationarity", stationarity_json(s.stationarity)}};
}

const char* reason_text(rigdata::gfr::stop_reason r) {
  switch (r) {
    case rigdata::gfr::stop_reason::duration:
      return "the duration was recorded";
    case rigdata::gfr::stop_reason::signal:
      return "stopped by a signal";
    case rigdata::gfr::stop_reason::link_lost:
      return "the port did not come back";
    case rigdata::gfr::stop_reason::device_changed:
      return "another device answered";
    case rigdata::gfr::stop_reason::device_failed:
      return "the device could not be started again after a reset";
    case rigdata::gfr::stop_reason::disk_full:
      return "the disk was full";
  }
  return "";
}

}  // namespace

int run_record(const record_options& o) {
  if (o.output == "-")
    return report(
        usage_error("-o -: a recording is a file (it is synced and read back), not "
                    "standard output; export it to CSV for a pipe"));
  if (o.baud == 0 || o.baud > 4000000)
    return report(usage_error("--baud must be a rate from 1 to 4000000 b/s (the rig: 115200)"));
  if (!(o.duration_s >= 0.0) || !std::isfinite(o.duration_s))
    return report(usage_error("--duration must be 0 (until stopped) or a positive number of s"));
  if (!(o.reconnect_timeout_s >= 0.0) || !std::isfinite(o.reconnect_timeout_s))
    return report(usage_error("--reconnect-timeout must be a number of s >= 0"));
  // The same bounds the reader of a recording applies (rigdata::check_units): what is recorded
  // can always be read back.
  if (!rigdata::check_units({"", 1.0, o.temp_mv_per_c * 1e-3, o.temp_at_0v_c, {}}, ""))
    return report(usage_error(
        "--temp-mv-per-c must be 0.001 to 10000 mV/degC (either sign) and --temp-at-0v a "
        "temperature from -273.15 to 1000 degC"));
  if (!o.table_axis.empty()) {
    if (auto a = earth::parse_axis(o.table_axis); !a)
      return report(usage_error(
          fmt::format("--table-axis '{}': {}", printable(o.table_axis, 60), a.err().message)));
  }
  if (o.azimuth_deg && !(std::fabs(*o.azimuth_deg) <= 360.0))
    return report(
        usage_error("--azimuth must be an angle from -360 to 360 deg (from north, "
                    "clockwise)"));
  auto dev = device_config(o);
  if (!dev) return report(dev.err());
  auto preset = sensor::load_preset(o.sensor);
  if (!preset) return report(preset.err());
  host::recorder_config c;
  c.port = o.port;
  c.baud = o.baud;
  c.output = o.output;
  c.duration_s = o.duration_s;
  c.rig = *dev;
  c.units.sensor = preset->name;
  c.units.scale_factor_v_per_dps = preset->params.scale_factor_v_per_dps;
  // The whole model goes into the recording (META's sensor_params), so the file carries the
  // specification its runs are checked against, as a simulated run's header does.
  for (const auto& f : sensor::fields())
    c.units.sensor_params.emplace_back(std::string(f.key), preset->params.*f.member);
  c.units.temp_v_per_c = o.temp_mv_per_c * 1e-3;
  c.units.temp_at_0v_c = o.temp_at_0v_c;
  c.mount.table_axis = o.table_axis;
  c.mount.azimuth_deg = o.azimuth_deg;
  c.reconnect_timeout_s = o.reconnect_timeout_s;
  // The run is tested as it grows, against the sensor's noise and specification: a turning
  // table or a moving bench is told while it can still be fixed (issue 31). The specification is
  // the one calibrate and report take from the finished file (workflow::resolve_sensor_spec of
  // the header it will carry), so the live verdict is theirs; --sensor is what that header
  // names, so there is no other part for it to contradict.
  std::vector<std::string> spec_warnings;
  auto spec = workflow::resolve_sensor_spec(std::nullopt, rigdata::sensor_metadata(c.units),
                                            o.output, false, spec_warnings);
  if (!spec) return report(spec.err());
  for (const auto& w : spec_warnings)
    std::fprintf(stderr, "gyroflip record: warning: %s\n", w.c_str());
  // The live cycles' scheme (abba; three or more positions: harmonic, issue 33).
  c.stationarity = workflow::stationarity_inputs_of(host::live_pairing(c.rig.table()),
                                                    *spec ? &**spec : nullptr, {});
  c.software_version = GYROFLIP_VERSION;
  c.command_line = o.command_line;

  const std::atomic<bool>& stop = catch_stop_signals({SIGINT, SIGTERM, SIGHUP});
  // A file size limit (ulimit -f) is a full disk: the write fails (EFBIG) and the run ends as
  // on ENOSPC - STOP to the device, a message, the file readable - instead of the default
  // action of SIGXFSZ, which kills the recorder mid-run without a word.
  std::signal(SIGXFSZ, SIG_IGN);

  const bool tty = isatty(STDERR_FILENO) != 0;
  bool drawn = false;
  bool warned = false;  // the live stationarity warning is given once
  bool warned_serial = false;
  const auto progress = [&](const host::recorder_status& s) {
    if (!warned_serial && s.serial && *s.serial == 0) {
      warned_serial = true;
      if (drawn) std::fputs("\r\033[K", stderr);
      std::fprintf(stderr,
                   "gyroflip record: warning: %s: the board has no serial (0: its information "
                   "flash holds no serial record): after a lost line it cannot be told from "
                   "another board, so the recording will end there; store one "
                   "(docs/HARDWARE.md, bring-up step 5)\n",
                   o.port.c_str());
    }
    if (!warned && s.stationarity && s.stationarity->failed()) {
      warned = true;
      if (drawn) std::fputs("\r\033[K", stderr);
      std::fprintf(stderr, "gyroflip record: warning: after %zu cycles, %s\n",
                   s.stationarity->cycles,
                   workflow::stationarity_warning(o.output, *s.stationarity).c_str());
    }
    if (o.json_progress) {
      fmt::print("{}\n", json_of(s).dump());
      std::fflush(stdout);
    } else if (tty) {
      draw(s);
      drawn = true;
    }
  };
  auto r = host::record(c, stop, progress);
  if (drawn) std::fputs("\r\033[K", stderr);
  if (!r) return report(r.err());
  const auto& s = r->last;
  // Lost dwells apart from the other frames lost (review of issue 32: "49-55 lost" on a line
  // whose every dwell was recorded were STATUS frames and replies, which the device does not
  // keep for RESEND).
  const std::uint64_t other = s.frames_lost - std::min(s.frames_lost, s.dwells_lost);
  std::fprintf(
      stderr,
      "gyroflip record: %s: %zu dwells, %zu cycles, %llu frames (%llu damaged on the line, %llu "
      "sent again); lost: %llu %s, %llu other %s%s over %.1f s: %s\n",
      o.output.c_str(), s.dwells, s.cycles, static_cast<unsigned long long>(s.frames_good),
      static_cast<unsigned long long>(s.frames_corrupt),
      static_cast<unsigned long long>(s.frames_recovered),
      static_cast<unsigned long long>(s.dwells_lost), s.dwells_lost == 1 ? "dwell" : "dwells",
      static_cast<unsigned long long>(other), other == 1 ? "frame" : "frames",
      other == 0 ? ""
                 : " (STATUS frames and command replies, which the device does not keep for "
                   "RESEND, or frames after a run's last dwell)",
      s.elapsed_s, reason_text(r->reason));
  // Runs after the first are placed by the host's clock: where the device's ran at another pace
  // (an emulator at --speed) their time_s are off, and the reader says by how much, naming each
  // run (review of issue 32, finding 4); the same warnings as `export`'s.
  if (auto back = rigdata::read_rig_run(o.output); back && back->later_runs_off_pace)
    for (const auto& w : back->warnings)
      if (w.find("by the host's clock") != std::string::npos)
        std::fprintf(stderr, "gyroflip record: warning: %s\n", w.c_str());
  if (s.stationarity && s.stationarity->checked)
    std::fprintf(stderr, "gyroflip record: %s\n",
                 s.stationarity->failed()
                     ? workflow::stationarity_warning(o.output, *s.stationarity).c_str()
                     : (o.output + ": " + s.stationarity->summary()).c_str());
  if (r->reason == rigdata::gfr::stop_reason::link_lost)
    return report(runtime_error(
        fmt::format("{}: the port did not come back within {:g} s; {} is complete up to the loss",
                    o.port, o.reconnect_timeout_s, o.output)));
  return 0;
}

}  // namespace gyroflip::app
