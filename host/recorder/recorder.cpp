/// \file
/// \brief The recorder's session with the rig (recorder.hpp, docs/RECORDER.md).
#include "host/recorder/recorder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <thread>
#include <type_traits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "firmware/ports/msp430f149/limits.hpp"
#include "firmware/protocol/budget.hpp"
#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"
#include "firmware/protocol/status.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/flip_stream.hpp"
#include "gyroflip/method/stationarity.hpp"
#include "host/serial/serial_port.hpp"

namespace gyroflip::host {

namespace {

using steady = std::chrono::steady_clock;
namespace p = protocol;
namespace gfr = rigdata::gfr;

const char* status_name(std::uint8_t s) {
  switch (static_cast<p::status>(s)) {
    case p::status::ok:
      return "ok";
    case p::status::bad_arg:
      return "a value out of range";
    case p::status::bad_frame:
      return "a malformed frame";
    case p::status::crc_mismatch:
      return "a damaged frame";
    case p::status::overflow:
      return "a buffer overflow";
    case p::status::timeout:
      return "a timeout";
    case p::status::bus_error:
      return "a bus error";
    case p::status::not_supported:
      return "not supported by this firmware";
    case p::status::busy:
      return "busy";
    case p::status::hw_fault:
      return "a hardware fault (a clock: see its ERROR)";
    case p::status::config_mismatch:
      return "another configuration than the one sent (the device rebooted)";
  }
  return "an unknown reason";
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string meta_json(const recorder_config& c) {
  nlohmann::json j{{"format", "gyroflip rig recording"},
                   {"gyroflip_version", c.software_version},
                   {"command_line", c.command_line},
                   {"start_utc", utc_now()},
                   {"port", c.port},
                   {"baud", c.baud},
                   {"duration_s", c.duration_s},
                   {"sensor", c.units.sensor},
                   {"scale_factor_v_per_dps", c.units.scale_factor_v_per_dps},
                   {"temp_v_per_c", c.units.temp_v_per_c},
                   {"temp_at_0v_c", c.units.temp_at_0v_c}};
  // Where the rig stands (issue 33): what `heading` and `calibrate`'s separability report read.
  if (!c.mount.table_axis.empty()) j["table_axis"] = c.mount.table_axis;
  if (c.mount.azimuth_deg) j["azimuth_deg"] = *c.mount.azimuth_deg;
  if (!c.units.sensor_params.empty()) {
    nlohmann::json params = nlohmann::json::object();
    for (const auto& [key, value] : c.units.sensor_params) params[key] = value;
    j["sensor_params"] = std::move(params);
  }
  // The command line and names may hold any bytes: never fail on them.
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

error foreign_protocol(const std::string& port, unsigned version) {
  return input_error({port}, fmt::format("the device speaks protocol version {}; this gyroflip "
                                         "speaks version {}: update the one that is older",
                                         version, p::protocol_version));
}

template <class M>
std::vector<std::uint8_t> payload_of(const M& m) {
  std::vector<std::uint8_t> b(p::max_payload);
  p::writer w{b.data(), b.size()};
  m.put(w);
  b.resize(w.n);
  return b;
}

// The device's frames as the recorder tracks them within one session of the device (between
// two resets): sequence numbers unwrapped to 64 bits, the missing ones remembered until they
// arrive (asked for with RESEND) or are given up (the device no longer has them).
class receive_window {
 public:
  enum class arrival { fresh, recovered, repeat };

  void reset() {
    have_ = false;
    missing_.clear();
  }
  /// Where `seq` stands against the highest number seen: > 0 ahead, <= 0 at or behind it.
  [[nodiscard]] std::int32_t distance(std::uint16_t seq) const {
    return static_cast<std::int16_t>(static_cast<std::uint16_t>(seq - highest_));
  }
  arrival arrive(std::uint16_t seq) {
    if (!have_) {
      have_ = true;
      highest_ = seq;
      return arrival::fresh;
    }
    const std::uint64_t s = unwrap(seq);
    if (s > highest_) {
      for (std::uint64_t m = highest_ + 1; m < s; ++m) missing_.emplace(m, miss{});
      highest_ = s;
      return arrival::fresh;
    }
    return missing_.erase(s) != 0 ? arrival::recovered : arrival::repeat;
  }
  /// Up to `max` missing sequence numbers not asked for within `interval_s`, oldest first;
  /// each is marked asked.
  std::vector<std::uint16_t> due(double interval_s, std::size_t max) {
    std::vector<std::uint16_t> out;
    const auto now = steady::now();
    for (auto& [s, m] : missing_) {
      if (out.size() == max) break;
      if (m.last != steady::time_point{} &&
          std::chrono::duration<double>(now - m.last).count() < interval_s)
        continue;
      ++m.asked;
      m.last = now;
      out.push_back(static_cast<std::uint16_t>(s));
    }
    return out;
  }
  /// Gives up `seq` (GONE); true when it was missing. A number past the highest seen was sent
  /// (the device names only those), so the ones between are missing.
  bool give_up(std::uint16_t seq) {
    if (!have_) return false;
    const std::uint64_t s = unwrap(seq);
    if (s > highest_) {
      for (std::uint64_t m = highest_ + 1; m < s; ++m) missing_.emplace(m, miss{});
      highest_ = s;
      return true;
    }
    return missing_.erase(s) != 0;
  }
  /// The number after the highest seen.
  [[nodiscard]] std::uint16_t next() const { return static_cast<std::uint16_t>(highest_ + 1); }
  /// The highest number seen, unwrapped.
  [[nodiscard]] std::uint64_t highest() const noexcept { return highest_; }
  [[nodiscard]] bool started() const noexcept { return have_; }
  /// Gives up everything older than `oldest` (the oldest frame the device still holds), and
  /// what was asked for `max_asks` times: how many.
  std::size_t give_up_older(std::uint16_t oldest, int max_asks) {
    if (!have_) return 0;
    const std::uint64_t o = unwrap(oldest);
    return std::erase_if(missing_,
                         [&](const auto& e) { return e.first < o || e.second.asked >= max_asks; });
  }
  std::size_t give_up_all() {
    const std::size_t n = missing_.size();
    missing_.clear();
    return n;
  }
  [[nodiscard]] std::size_t missing() const noexcept { return missing_.size(); }

 private:
  struct miss {
    int asked = 0;
    steady::time_point last{};
  };
  // The 64-bit number nearest the highest seen with these low 16 bits.
  [[nodiscard]] std::uint64_t unwrap(std::uint16_t seq) const {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(highest_) + distance(seq));
  }
  bool have_ = false;
  std::uint64_t highest_ = 0;
  std::map<std::uint64_t, miss> missing_;
};

// The pair of positions the live cycles use (method::flip_pair_of); a table without one holds no
// position of it, so that it gives no live cycles.
method::flip_pair live_pair(const position_table& table) {
  auto p = method::flip_pair_of(table, "");
  return p ? *p : method::flip_pair{table_moving - 1, table_moving - 1};
}

// The live cycles' demodulator (live_pairing): abba over the table's pair, or the harmonic scheme.
std::unique_ptr<method::demodulator> live_demodulator(const position_table& table) {
  if (live_pairing(table) == method::pairing::harmonic)
    if (auto d = method::make_demodulator(method::pairing::harmonic, table, ""))
      return std::move(*d);
  return method::make_flip_demodulator(method::pairing::abba, live_pair(table));
}

// A non-data frame (INFO, STATUS, ACK, NAK, GONE, RAW) is sent once, in the order of its
// number: one whose number is not past every number heard from this boot comes from another
// boot. So does a frame far ahead of them: the recorder reads all the time, and a boot's frames
// do not run thousands of numbers ahead of what it heard (a long stall of the recorder only
// costs a re-homing; docs/RECORDER.md).
constexpr std::int32_t max_plausible_ahead = 2048;

class session {
 public:
  session(const recorder_config& c, gfr::writer w, port_lock name_lock,
          const std::atomic<bool>& stop, const recorder_progress_fn& fn)
      : c_(c),
        file_(std::move(w)),
        name_lock_(std::move(name_lock)),
        stop_(stop),
        on_progress_(fn),
        live_(c.output, false) {
    // A fresh command numbering for every session: a command the device remembers from another
    // run is never taken for a retry of this one's.
    std::random_device rd;
    seq_ = static_cast<std::uint16_t>(rd());
  }

  result<recorder_result> run();

 private:
  // What an acknowledged command leaves in the file, written when its ACK is read (so that a
  // reset seen in the same read comes after it).
  enum class on_ack { none, configure, start };

  // The link.
  status open_port();
  template <class M>
  status send(const M& m, std::uint16_t seq);
  status pump(int timeout_ms);
  status on_frame(const p::frame& f);
  status on_info(const p::frame& f, const p::info_msg& m);
  status identify(const p::info_msg& m);
  error end_unserialled();
  [[nodiscard]] bool says_reset(const p::frame& f, bool identifying) const;
  status note_reset();
  result<p::info_msg> ping();
  template <class M>
  status command(const M& m, const char* name, on_ack then = on_ack::none);
  status start_run();
  status begin_recording(std::uint16_t ack_seq, std::uint16_t config_crc);
  status request_missing();
  status keep_up();
  status probe();
  status drain_missing();
  status handle_reset();
  result<bool> reconnect(steady::time_point lost_at);
  result<recorder_result> finish(gfr::stop_reason why);
  // The file.
  status append(gfr::kind k, std::span<const std::uint8_t> body = {});
  status append_frame(const p::frame& f);
  status append_gap(gfr::gap_reason r, std::uint32_t count);
  // The STOP record with its reason, then the file closed (synced).
  status close_file(gfr::stop_reason why);
  status note_lost(std::size_t n);
  status note_corrupt();
  void note_unstored(gfr::kind k, std::span<const std::uint8_t> body);
  error end_disk_full();
  void note_dwell_time(const p::frame& f);
  void close_segment();
  status tick();
  [[nodiscard]] recorder_status status_now() const;
  void look(bool last);
  [[nodiscard]] double data_s() const {
    const double hz = info_ && info_->tick_hz != 0 ? info_->tick_hz : 1.0;
    return data_closed_s_ + static_cast<double>(seg_span_ticks_) / hz;
  }
  // A missing frame is asked for again every 0.15 s of the device's time (a round trip on the
  // line is tens of ms): its history (~6 s) allows ~40 tries. It is given up when STATUS says
  // the history no longer holds it, or after 80 asks (a device that never says so).
  [[nodiscard]] double resend_interval_s() const {
    return std::clamp(0.15 / device_speed_, 0.001, 0.15);
  }
  // How long a read waits for bytes: short when the device runs fast (an emulator), so that a
  // RESEND due within ms goes out in time.
  [[nodiscard]] int read_wait_ms() const {
    return static_cast<int>(std::clamp(resend_interval_s() * 1e3, 1.0, 20.0));
  }
  // How long a PING waits for its INFO, and how often a vanished port is looked for: the rig's
  // times, shorter in wall time when its clock runs faster (the device's history is device
  // time: a 3-s unplug of an emulator at 50x must be over in 60 ms of ours to lose nothing).
  [[nodiscard]] double ping_wait_s() const {
    return std::clamp(c_.reply_timeout_s / 4 / device_speed_, 0.05, c_.reply_timeout_s / 4);
  }
  [[nodiscard]] double port_poll_s() const { return std::clamp(0.2 / device_speed_, 0.002, 0.2); }
  // Nothing at all arrived for longer than 0.15 s of ours and 1.2 STATUS periods of the
  // device's: it is not running on (an emulator stopped, a device hung), as opposed to a line
  // that loses its frames. Missing frames are then not asked for (nothing would answer, and a
  // backlog of RESENDs answered at once when it runs again would flood the line), and a probe
  // goes at most every 0.5 s of ours.
  [[nodiscard]] bool line_silent() const {
    const double period_s = running_.status_period_ms != 0 ? running_.status_period_ms / 1e3 : 1.0;
    const double quiet_s = std::max(0.15, 1.2 * period_s / device_speed_);
    return std::chrono::duration<double>(steady::now() - last_byte_).count() > quiet_s;
  }
  [[nodiscard]] std::uint64_t host_us() const {
    return static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::microseconds>(steady::now() - t0_).count());
  }
  [[nodiscard]] error interrupted() const {
    return runtime_error(fmt::format("{}: interrupted before the rig answered", c_.port));
  }

  const recorder_config& c_;
  p::configure_msg running_ = c_.rig.to_configure();  // what the device runs with
  gfr::writer file_;
  port_lock name_lock_;                   // the port's name, held all session
  std::optional<port_lock> device_lock_;  // the device it named at the last open
  const std::atomic<bool>& stop_;
  const recorder_progress_fn& on_progress_;
  rigdata::rig_run_builder live_;
  std::size_t records_ = 0;
  // The live cycles (live_pairing): abba over the pair of the table the session configures (a
  // table of two without one gives none), or for three or more positions the harmonic scheme.
  method::flip_stream stream_{live_demodulator(c_.rig.table())};
  std::vector<method::cycle> cycles_;
  std::size_t dwells_seen_ = 0;
  std::optional<method::stationarity> stationarity_;  // the last live test (look())
  std::size_t next_look_ = method::first_live_look_cycles;

  std::optional<serial_port> port_;
  p::stream_decoder dec_{true};  // retransmitted (older) frames are handed out too
  p::frame_decoder old_dec_;     // the same bytes as protocol v1 framed them (foreign devices)
  receive_window window_;
  std::optional<p::info_msg> info_;      // the session's device (serial, boot count)
  std::optional<p::info_msg> got_info_;  // the INFO a PING brought
  std::optional<error> fatal_;           // a reason to end the run found while reading
  // The file took no more (a full disk, a file size limit, a failed write or sync): the run
  // ends (end_disk_full); what arrives meanwhile is counted, not stored.
  std::optional<error> disk_error_;
  std::uint64_t unstored_frames_ = 0;             // frames that arrived and could not be stored
  std::uint64_t unstored_dwells_ = 0;             // ... of them DWELLs
  std::uint64_t unstored_raws_ = 0;               // ... and RAW frames
  std::uint64_t unstored_gap_ = 0;                // frames counted lost by GAP records not stored
  steady::time_point lost_at_{};                  // when the port was lost (the GAP's milliseconds)
  std::uint64_t epoch_ = 0;                       // device resets seen: a command is of one epoch
  steady::time_point speed_at_{};                 // the device_speed_ estimate's start
  double device_speed_ = 1.0;                     // device seconds per wall second
  steady::time_point last_fresh_{};               // a new frame of the device arrived
  steady::time_point last_byte_ = steady::now();  // any byte arrived
  steady::time_point last_probe_{};
  std::uint64_t reply_epoch_ = 0;  // the epoch of the command waiting for its reply
  // What a reset costs besides the numbers still missing: what the old boot sent while the
  // line was gone, from its frame rate (frames per second of ours since its first frame
  // heard): nothing of those frames reached the line.
  steady::time_point rate_at_{};
  std::uint64_t rate_seq_ = 0;
  // Data time (--duration): the device-clock span of each segment's dwells, summed.
  double data_closed_s_ = 0.0;
  std::uint64_t seg_span_ticks_ = 0;
  std::uint64_t recovered_ = 0, lost_ = 0;
  steady::time_point t0_ = steady::now();
  steady::time_point last_tick_ = steady::now();

  std::uint32_t noted_bad_ = 0;
  int restart_failures_ = 0;  // start attempts in a row that failed (no dwell since)
  std::uint32_t last_uptime_ = 0;
  std::uint32_t speed_uptime_ = 0;  // the device_speed_ estimate's start
  on_ack reply_then_ = on_ack::none;
  // ... and the damaged frames since the boot's last good one, and the highest plausible number
  // a damaged frame's header named (frames the old boot sent and the line lost).
  std::uint32_t bad_at_last_good_ = 0;
  std::int32_t damaged_ahead_ = 0;
  std::uint32_t seg_max_end_ = 0;       // the latest dwell end of the segment (device ticks)
  std::int64_t seg_max_end_off_ = 0;    // ... and its place from the segment's first dwell end
  std::int64_t seg_min_start_off_ = 0;  // the earliest dwell start, placed the same way
  // Dwells missing from the runs (review of issue 32: `lost` counted STATUS frames and replies,
  // which the device does not keep for RESEND, with the dwells): the segment's dwell indices
  // (n_positions x cycle + position) not seen below the highest one seen, as the reader counts
  // them; some may still come back on RESEND.
  std::set<std::uint64_t> seg_missing_k_;
  std::uint64_t seg_next_k_ = 0;
  std::uint64_t dwells_missing_closed_ = 0;
  std::uint16_t seq_ = 0;
  // The command waiting for its reply.
  std::optional<std::uint16_t> reply_seq_;
  // This boot's CONFIGURE acknowledged (the first ACK's number), and a START sent for it whose
  // ACK has not come: a frame of a run after that number says the START began the run.
  std::optional<std::uint16_t> configured_at_;
  std::optional<std::uint16_t> start_ack_seq_;
  std::optional<std::uint8_t> reply_nak_;  // reason, when the reply was a NAK
  std::uint8_t reply_type_ = 0;
  bool start_in_flight_ = false;
  bool run_evidence_ = false;
  bool replied_ = false;
  bool resend_now_ = false;  // the device said our command arrived damaged
  bool recording_ = false;   // a START was acknowledged: the run is on
  bool ever_started_ = false;
  bool stopping_ = false;
  bool waiting_info_ = false;
  // The line's frames are the session device's: false from a (re)opened port until an INFO
  // names the board (its serial). Nothing of the line is stored before.
  bool identified_ = false;
  bool identify_record_ = false;  // the INFO that identified the board goes into the file
  bool reset_seen_ = false;       // the device rebooted: re-home, re-configure, START
  bool need_info_ = false;        // ... and its INFO is still to be recorded
  bool restart_ = false;          // the last command was cut short by a reset
  bool device_idle_ = false;      // a STATUS said idle while we record
  bool have_uptime_ = false;
  // The boot count a STATUS of a rebooted device gave before its INFO was recorded: an INFO or
  // STATUS of another boot count meanwhile is a further reset.
  std::optional<std::uint16_t> unnamed_boot_;
  bool since_link_loss_ = false;  // the line was gone: the rate above counts what it lost
  bool have_rate_ = false;
  bool seg_started_ = false;
  bool waiting_for_port_ = false;
  bool link_down_ = false;  // the last error came from the port, not the file
};

// Every record goes into the file as it is made. One the file cannot take (disk_error_) is
// counted instead (note_unstored): the run ends at the main loop's next turn, and the GAP that
// closes the file counts it.
status session::append(gfr::kind k, std::span<const std::uint8_t> body) {
  gfr::record r{k, host_us(), {body.begin(), body.end()}};
  if (!disk_error_)
    if (auto s = file_.append(k, r.host_time_us, body); !s) disk_error_ = s.err();
  if (disk_error_) {
    note_unstored(k, body);
    return ok();
  }
  if (auto s = live_.add(r, ++records_); !s) return s;
  const auto& dw = live_.run().dwells;
  if (dwells_seen_ == dw.size()) return ok();
  const position_table table = rigdata::positions_of(live_.run());
  for (; dwells_seen_ < dw.size(); ++dwells_seen_)
    if (auto row = rigdata::dwell_row(dw[dwells_seen_], table))
      stream_.push(*row, [this](const method::cycle& cy) { cycles_.push_back(cy); });
  return ok();
}

status session::append_frame(const p::frame& f) {
  std::uint8_t body[3 + p::max_payload];
  p::writer w{body, sizeof body};
  w.u8(f.type);
  w.u16(f.seq);
  std::copy_n(f.payload, f.length, w.take(f.length));
  return append(gfr::kind::frame, {body, w.n});
}

status session::close_file(gfr::stop_reason why) {
  const std::uint8_t body[1] = {static_cast<std::uint8_t>(why)};
  if (auto s = append(gfr::kind::stop, body); !s) return s;
  if (disk_error_) return *disk_error_;
  return file_.close();  // syncs
}

// A record the file could not take: a frame (an INFO record is a frame of the device's numbering
// too) is lost to the file, and so are the frames a GAP (missing) counted.
void session::note_unstored(gfr::kind k, std::span<const std::uint8_t> body) {
  if (k == gfr::kind::frame || k == gfr::kind::info) {
    ++unstored_frames_;
    if (k == gfr::kind::frame && !body.empty() &&
        body[0] == static_cast<std::uint8_t>(p::msg::dwell))
      ++unstored_dwells_;
    if (k == gfr::kind::frame && !body.empty() && body[0] == static_cast<std::uint8_t>(p::msg::raw))
      ++unstored_raws_;
  } else if (k == gfr::kind::gap && body.size() == 5 &&
             body[0] == static_cast<std::uint8_t>(gfr::gap_reason::missing)) {
    p::reader r{body.data() + 1, 4};
    unstored_gap_ += r.u32();
  }
}

// The file took no more (a full disk, a file size limit, a failed write or sync; review of
// issue 32: the dwell whose write failed was in no count, no STOP was written, and `export` blamed
// a kill). The writer cut the failed record back to the last whole one. The device gets STOP
// (what it sends until then is counted), then, if the room the cut left holds them, a GAP
// (missing) counts every frame of this boot that is not in the file and a STOP record says why;
// the file is synced and closed, and the message names the file and what was lost.
error session::end_disk_full() {
  if (port_ && !stopping_) {
    stopping_ = true;
    (void)command(p::stop_msg{}, "STOP");
    (void)pump(100);
  }
  const std::size_t missing = window_.give_up_all();
  lost_ += missing + unstored_frames_;
  std::uint64_t not_stored = missing + unstored_frames_ + unstored_gap_;
  // A GAP (missing) counting what is not stored.
  const auto write_gap = [&] {
    std::uint8_t b[5];
    p::writer w{b, sizeof b};
    w.u8(static_cast<std::uint8_t>(gfr::gap_reason::missing));
    w.u32(static_cast<std::uint32_t>(std::min<std::uint64_t>(not_stored, 0xFFFFFFFFu)));
    return static_cast<bool>(file_.append_last(gfr::kind::gap, host_us(), b));
  };
  // The GAP (when something is not stored) and the STOP; false, and neither left in the file,
  // when they did not both fit.
  const auto write_end = [&] {
    const std::uint64_t at = file_.bytes();
    if (not_stored != 0 && !write_gap()) return false;
    const std::uint8_t stop[1] = {static_cast<std::uint8_t>(gfr::stop_reason::disk_full)};
    if (file_.append_last(gfr::kind::stop, host_us(), stop)) return true;
    if (file_.bytes() != at) (void)file_.take_back_last();  // the GAP: written again below
    return false;
  };
  bool closed = write_end();
  // A full disk whose room the writer could not know (ENOSPC; a size limit set after the file
  // was made) may leave less than the 48 bytes those two take after the failed record was cut
  // back: the last frames go back out of the file, one at a time, until they fit, and are
  // counted in the GAP with what else was not stored - the file then says why it ends, and
  // nothing the device sent is left uncounted (review of issue 32: the file had no STOP, its
  // readers blamed a kill, and the dwell whose write failed was counted nowhere). Only FRAME
  // records (and the writer's own COPYs) go back; an INFO, CONFIGURE or START stays.
  std::uint64_t taken_frames = 0, taken_dwells = 0;
  while (!closed) {
    const auto last = file_.last_record();
    if (!last || (last->type != gfr::kind::frame && last->type != gfr::kind::copy)) break;
    if (!file_.take_back_last()) break;
    if (last->type == gfr::kind::frame) {
      ++taken_frames;
      ++unstored_frames_;
      ++not_stored;
      ++lost_;
      if (last->first == static_cast<std::uint8_t>(p::msg::dwell)) {
        ++taken_dwells;
        ++unstored_dwells_;
      }
      if (last->first == static_cast<std::uint8_t>(p::msg::raw)) ++unstored_raws_;
    }
    closed = write_end();
  }
  bool counted = not_stored == 0 || closed;
  if (!closed && not_stored != 0) counted = write_gap();  // the GAP alone, then
  const bool synced = static_cast<bool>(file_.close());   // copies if they fit; synced
  const auto n_of = [](std::uint64_t n, const char* one, const char* many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
  };
  const std::uint64_t given_up = missing + unstored_gap_;
  const std::string taken =
      taken_frames == 0
          ? std::string()
          : fmt::format(
                "; to make room for the records that end it, its last {} ({}) went back out of "
                "the file and {} counted with them",
                n_of(taken_frames, "frame", "frames"), n_of(taken_dwells, "DWELL", "DWELLs"),
                taken_frames == 1 ? "is" : "are");
  const std::string what =
      not_stored == 0
          ? std::string("nothing the device sent was lost")
          : fmt::format(
                "{} the device sent {} not in the file ({}, {} and {} (STATUS, replies) that "
                "arrived and could not be stored, and {} still missing: damaged or dropped on the "
                "line, of any kind){}",
                n_of(not_stored, "frame", "frames"), not_stored == 1 ? "is" : "are",
                n_of(unstored_dwells_, "DWELL", "DWELLs"),
                n_of(unstored_raws_, "RAW frame", "RAW frames"),
                n_of(unstored_frames_ - unstored_dwells_ - unstored_raws_, "other frame",
                     "other frames"),
                n_of(given_up, "frame", "frames"),
                counted ? ", counted lost in a GAP record"
                        : "; the file had no room left to count them in a GAP record");
  return runtime_error(fmt::format(
      "{}; the recording ends here and the device was stopped: {}{}; everything recorded before "
      "is in {} ({}){}",
      disk_error_->message, what, taken, c_.output,
      closed ? "it ends with a STOP record: the disk was full"
             : "there was no room left for its STOP record either: its readers will say it was "
               "not closed",
      synced ? "" : "; the file could not be synced: what the kernel still held may be lost"));
}

status session::append_gap(gfr::gap_reason r, std::uint32_t count) {
  std::uint8_t b[5];
  p::writer w{b, sizeof b};
  w.u8(static_cast<std::uint8_t>(r));
  w.u32(count);
  return append(gfr::kind::gap, b);
}

// Frames given up: the device no longer has them. Only these are lost.
status session::note_lost(std::size_t n) {
  if (n == 0) return ok();
  lost_ += n;
  return append_gap(gfr::gap_reason::missing, static_cast<std::uint32_t>(n));
}

// Frames the decoder dropped since the last call (damaged on the line; RESEND brings most back).
status session::note_corrupt() {
  const std::uint32_t bad = dec_.counts().bad();
  if (bad == noted_bad_) return ok();
  const std::uint32_t n = bad - noted_bad_;
  noted_bad_ = bad;
  return append_gap(gfr::gap_reason::corrupt, n);
}

// A DWELL of the run in the current segment: its span on the device clock grows (32-bit ticks
// unwrapped against the latest end seen; one sent again is inside the span already, one that
// comes back on RESEND from before the first one seen widens it). The run's dwells count from
// the START (or, while START's ACK is awaited, from this boot's CONFIGURE: the device was idle
// from it until the START began the run, whose ACK may never come): a recording of "600 s"
// holds 600 s of dwells whatever their START's replies did (issue 32).
void session::note_dwell_time(const p::frame& f) {
  p::dwell_msg d;
  const auto after = [&](const std::optional<std::uint16_t>& at) {
    return at && static_cast<std::int16_t>(static_cast<std::uint16_t>(f.seq - *at)) > 0;
  };
  const bool of_run =
      (recording_ && after(start_ack_seq_)) || (start_in_flight_ && after(configured_at_));
  if (!of_run || !f.as(d)) return;
  // Its place in the run, and the ones skipped before it (a cap keeps a wild index from taking
  // memory: 2^20 dwells are 12 days of the paper's rig).
  const std::uint64_t k = std::uint64_t{running_.n_positions} * d.cycle + d.position;
  if (k >= seg_next_k_) {
    for (std::uint64_t j = seg_next_k_; j < k && seg_missing_k_.size() < (1u << 20); ++j)
      seg_missing_k_.insert(j);
    seg_next_k_ = k + 1;
  } else {
    seg_missing_k_.erase(k);
  }
  if (!seg_started_) {
    seg_started_ = true;
    seg_max_end_ = d.t_end_ticks;
    seg_max_end_off_ = 0;
    seg_min_start_off_ = -static_cast<std::int64_t>(d.t_end_ticks - d.t_start_ticks);
  }
  const std::int64_t end_off =
      seg_max_end_off_ + static_cast<std::int32_t>(d.t_end_ticks - seg_max_end_);
  const std::int64_t start_off =
      end_off - static_cast<std::int64_t>(d.t_end_ticks - d.t_start_ticks);
  if (end_off > seg_max_end_off_) {
    seg_max_end_off_ = end_off;
    seg_max_end_ = d.t_end_ticks;
  }
  seg_min_start_off_ = std::min(seg_min_start_off_, start_off);
  seg_span_ticks_ = static_cast<std::uint64_t>(seg_max_end_off_ - seg_min_start_off_);
  restart_failures_ = 0;  // the device runs: a later restart starts its count again
}

// The segment ends (a reset, a restart): its data time is kept, the next one starts at 0.
void session::close_segment() {
  dwells_missing_closed_ += seg_missing_k_.size();
  seg_missing_k_.clear();
  seg_next_k_ = 0;
  data_closed_s_ = data_s();
  seg_started_ = false;
  seg_span_ticks_ = 0;
}

// What the run looks like now (the progress report and the result).
recorder_status session::status_now() const {
  recorder_status st;
  const auto& run = live_.run();
  st.elapsed_s = data_s();
  st.duration_s = c_.duration_s;
  st.dwells = run.dwells.size();
  st.cycles = cycles_.size();
  st.frames_good = run.frames;
  st.frames_corrupt = run.corrupt_frames;
  st.frames_recovered = recovered_;
  st.frames_lost = lost_;
  st.dwells_lost = dwells_missing_closed_ + seg_missing_k_.size();
  st.frames_pending = window_.missing();
  st.device_resets = run.device_resets;
  st.link_losses = run.link_losses;
  st.delta_n_dps = st.delta_n_se_dps = method::no_value;
  if (auto cal = method::calibrate(cycles_)) {
    st.delta_n_dps = cal->delta_n_dps;
    st.delta_n_se_dps = cal->stderr_correlated_dps;
  }
  st.temp_c = run.dwells.empty() ? method::no_value : run.dwells.back().temp_c;
  st.bytes = file_.bytes();
  st.waiting_for_port = waiting_for_port_;
  st.stationarity = stationarity_;
  if (info_) st.serial = info_->serial;
  return st;
}

// The live stationarity test (recorder_config::stationarity), when the cycles reach the next
// look, or at the end (`last`).
void session::look(bool last) {
  if (!c_.stationarity || (!last && cycles_.size() < next_look_)) return;
  const auto cal = method::calibrate(cycles_);
  if (!cal) return;
  stationarity_ = method::check_stationarity(cycles_, *cal, *c_.stationarity);
  next_look_ = method::next_stationarity_look(cycles_.size());
}

// About once a second: sync the file (what was acknowledged survives a power loss) and report.
status session::tick() {
  const auto now = steady::now();
  if (now - last_tick_ < std::chrono::seconds(1)) return ok();
  last_tick_ = now;
  if (!disk_error_)
    if (auto s = file_.sync(); !s) disk_error_ = s.err();  // the main loop ends the run
  look(false);
  if (on_progress_) on_progress_(status_now());
  return ok();
}

// Opens the port and holds the device it names now: a name that points elsewhere after a
// replug (a link to a new pty) takes that device's lock too.
status session::open_port() {
  auto key = port_lock::device_key(c_.port);
  if (!key) return key.err();
  if (!device_lock_ || device_lock_->key() != *key) {
    auto lock = port_lock::take(*key, c_.port);
    if (!lock) return lock.err();
    device_lock_.emplace(std::move(*lock));
  }
  auto port = serial_port::open(c_.port, c_.baud);
  if (!port) return port.err();
  port_.emplace(std::move(*port));
  identified_ = false;  // whoever answers on it is not known yet
  return ok();
}

template <class M>
status session::send(const M& m, std::uint16_t seq) {
  std::uint8_t buf[p::max_wire_bytes];
  const std::size_t n = p::encode_wire(m, seq, buf, sizeof buf, true);
  auto s = port_->write(buf, n, 1000);
  if (!s) link_down_ = true;
  return s;
}

// Whether frame `f` (of the identified board) says the device restarted since the session's
// INFO: its boot INFO (number 0: a boot's first frame), an INFO or STATUS with another boot
// count, a STATUS whose uptime went back (a power-on restarts the count and the clock), or a
// frame numbered where this boot's cannot be (max_plausible_ahead). Until the new boot's INFO
// is in, its frames say nothing more.
bool session::says_reset(const p::frame& f, bool identifying) const {
  if (!info_) return false;
  if (need_info_) {
    // A reset whose INFO is still to come: a STATUS has said the new boot's count, and the
    // device reset again before answering the PING (review of issue 32, fifth pass, finding 4:
    // the INFO that answered was the next boot's, and boot 2's frames and boot 3's shared one
    // segment with one reset recorded for two).
    if (!unnamed_boot_) return false;
    if (f.type == static_cast<std::uint8_t>(p::msg::info)) {
      p::info_msg m;
      return f.as(m) && m.boot_count != *unnamed_boot_;
    }
    if (f.type == static_cast<std::uint8_t>(p::msg::status)) {
      p::status_msg m;
      return f.as(m) &&
             (m.boot_count != *unnamed_boot_ || (have_uptime_ && m.uptime_ticks < last_uptime_ &&
                                                 last_uptime_ - m.uptime_ticks < 0x80000000u));
    }
    return false;
  }
  if (window_.started()) {
    // The INFO that names the board after a reconnect may be far ahead: the device ran on.
    const std::int32_t d = window_.distance(f.seq);
    if ((d > max_plausible_ahead && !identifying) || (d <= 0 && !p::kept_for_resend(f.type)))
      return true;
  }
  if (f.type == static_cast<std::uint8_t>(p::msg::info)) {
    p::info_msg m;
    return f.as(m) && (f.seq == 0 || m.boot_count != info_->boot_count);
  }
  if (f.type == static_cast<std::uint8_t>(p::msg::status)) {
    p::status_msg m;
    if (!f.as(m)) return false;
    const bool went_back = have_uptime_ && m.uptime_ticks < last_uptime_ &&
                           last_uptime_ - m.uptime_ticks < 0x80000000u;  // not a 32-bit wrap
    return m.boot_count != info_->boot_count || went_back;
  }
  return false;
}

// The device restarted: what it owed is lost (a GAP with their count: its history went with its
// RAM), its numbering starts again, and its INFO (the boot's, or a PING's) goes into the file
// after the gap. A command in flight is void (command() sees the epoch change): a command
// retried after a reset is not the same command.
status session::note_reset() {
  // A START whose ACK never came but whose run the old boot showed: its frames are that run's
  // (they follow this boot's CONFIGURE, after which the device was idle until the START).
  if (start_in_flight_ && run_evidence_ && configured_at_ && !recording_)
    if (auto s = begin_recording(*configured_at_, p::configure_crc(running_)); !s) return s;
  ++epoch_;
  reset_seen_ = true;
  need_info_ = true;
  recording_ = false;
  start_in_flight_ = run_evidence_ = false;
  configured_at_.reset();
  start_ack_seq_.reset();
  have_uptime_ = false;
  unnamed_boot_.reset();
  close_segment();
  // What the old boot still owed, and what it sent after the last frame heard of it and the
  // line damaged (each damaged frame, or the frames a damaged header numbered; the new boot's
  // first frames may be among them: a GAP counts at least what was lost).
  std::size_t tail = std::max<std::size_t>(dec_.counts().bad() - bad_at_last_good_,
                                           static_cast<std::size_t>(damaged_ahead_));
  damaged_ahead_ = 0;
  // A reset found after the line was gone: the old boot sent on while nothing could arrive, for
  // as long as it ran after its last frame heard (at most until now). Counted at its frame rate:
  // an upper bound (it may have reset earlier).
  if (since_link_loss_ && have_rate_ && last_fresh_ > rate_at_ && window_.highest() > rate_seq_) {
    const double per_s = static_cast<double>(window_.highest() - rate_seq_) /
                         std::chrono::duration<double>(last_fresh_ - rate_at_).count();
    const double gone_s = std::chrono::duration<double>(steady::now() - last_fresh_).count();
    tail += static_cast<std::size_t>(std::ceil(std::min(per_s * gone_s, 65535.0)));
  }
  have_rate_ = false;
  if (auto s = note_lost(window_.give_up_all() + tail); !s) return s;
  window_.reset();
  dec_.frames().reset_sequence();
  return append_gap(gfr::gap_reason::device_reset, 0);
}

// The board is named by an INFO after the port was (re)opened (the link-lost GAP goes first): the
// same serial goes on; another board, there or at any time, is refused and nothing of it is stored.
status session::identify(const p::info_msg& m) {
  if (!identified_) {  // after a reconnect: how long the line was gone
    waiting_for_port_ = false;
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(steady::now() - lost_at_);
    if (auto s = append_gap(gfr::gap_reason::link_lost, static_cast<std::uint32_t>(ms.count())); !s)
      return s;
  }
  if (m.serial != info_->serial) {
    fatal_ = runtime_error(
        fmt::format("{}: another device answered (serial {} instead of {}): it is not recorded "
                    "into the same file; {} is complete up to here",
                    c_.port, m.serial, info_->serial, c_.output));
    return ok();
  }
  identified_ = true;
  identify_record_ = true;
  // Damage before the board was named is counted from here (its frames come back on RESEND).
  bad_at_last_good_ = dec_.counts().bad();
  return ok();
}

// A board of serial 0 cannot be told from another board of serial 0: two of them powered up
// together have the same boot count, frame numbers and clock (review of issue 32: swapped cables,
// the second board taken for the first 5 times of 5). After its line is lost the recording ends:
// the link-lost GAP, what the window still missed counted lost, a STOP record (link lost), exit 1
// naming why; nothing that answers afterwards is stored (docs/RECORDER.md, "A board without a
// serial").
error session::end_unserialled() {
  port_.reset();
  identified_ = false;
  (void)note_lost(window_.give_up_all());
  (void)append_gap(gfr::gap_reason::link_lost, 0);
  (void)close_file(gfr::stop_reason::link_lost);
  return runtime_error(fmt::format(
      "{}: the line was lost and the board has no serial: after a lost line it cannot be told "
      "from another board, so the recording ends here; {} is complete up to the loss (store a "
      "serial in the board: docs/HARDWARE.md, bring-up step 5)",
      c_.port, c_.output));
}

// An INFO of the identified board: the answer to a PING, a boot's (a reset), or the one that
// identified it after a reconnect; each of the last two goes into the file as an INFO record.
status session::on_info(const p::frame& f, const p::info_msg& m) {
  if (waiting_info_) {
    got_info_ = m;
    waiting_info_ = false;
  }
  if (!need_info_ && !identify_record_) return append_frame(f);  // a PING's answer
  need_info_ = identify_record_ = false;
  unnamed_boot_.reset();
  info_ = m;
  return append(gfr::kind::info, payload_of(m));
}

status session::on_frame(const p::frame& f) {
  const auto type = static_cast<p::msg>(f.type);
  if (type == p::msg::ack || type == p::msg::nak) {
    p::ack_msg a;
    p::nak_msg n;
    const bool is_ack = f.as(a);
    const bool is_nak = !is_ack && f.as(n);
    const std::uint16_t of = is_ack ? a.seq : n.seq;
    const std::uint8_t of_type = is_ack ? a.of_type : n.of_type;
    // Only a reply of this boot to the command waiting: one from before a reset answered
    // another command.
    if (!(reply_seq_ && of == *reply_seq_ && of_type == reply_type_ && reply_epoch_ == epoch_))
      return ok();
    if (is_nak && n.reason == static_cast<std::uint8_t>(p::status::crc_mismatch)) {
      resend_now_ = true;  // our command arrived damaged: send it again at once
      return ok();
    }
    if (is_nak && n.reason == static_cast<std::uint8_t>(p::status::config_mismatch) &&
        of_type == static_cast<std::uint8_t>(p::msg::start)) {
      // The device no longer has the configuration this boot acknowledged: it rebooted (its
      // boot's frames were all lost). The START is void; the run restarts homed.
      return note_reset();
    }
    if (!is_ack && !is_nak) return ok();
    replied_ = true;
    if (is_nak) {
      reply_nak_ = n.reason;
      return ok();
    }
    // What the command leaves in the file, now: a reset read next comes after it.
    if (reply_then_ == on_ack::configure) {
      configured_at_ = a.at_seq;
      return append(gfr::kind::configure, payload_of(running_));
    }
    // Where the run began: the first ACK's number, also when only a retry's ACK came.
    if (reply_then_ == on_ack::start) return begin_recording(a.at_seq, p::configure_crc(running_));
    return ok();
  }
  // A run going on after this boot's CONFIGURE while our START waits for its ACK: the START
  // began it (the device was idle after CONFIGURE, and only this recorder starts it).
  const bool after_configure =
      configured_at_ &&
      static_cast<std::int16_t>(static_cast<std::uint16_t>(f.seq - *configured_at_)) > 0;
  if (start_in_flight_ && after_configure &&
      (type == p::msg::dwell || type == p::msg::raw || type == p::msg::compensated))
    run_evidence_ = true;
  if (type == p::msg::dwell) note_dwell_time(f);
  if (type == p::msg::gone) {
    p::gone_msg g;
    if (!f.as(g)) return ok();
    std::size_t n = 0;
    for (std::uint8_t i = 0; i < g.count; ++i) n += window_.give_up(g.seqs[i]) ? 1u : 0u;
    return note_lost(n);
  }
  if (type == p::msg::status) {
    p::status_msg m;
    if (!f.as(m)) return ok();
    if (start_in_flight_ && after_configure &&
        (m.state == static_cast<std::uint8_t>(p::device_state::running) ||
         m.state == static_cast<std::uint8_t>(p::device_state::homing)))
      run_evidence_ = true;
    // How fast the device's clock runs against ours (1 for a rig, more for an emulator at
    // --speed): a RESEND is repeated after a device-time interval, not a wall-clock one. Taken
    // over at least 50 ms of ours (STATUS frames read in one go would say "infinitely fast").
    const auto now = steady::now();
    if (!have_uptime_ || m.uptime_ticks < speed_uptime_) {
      speed_uptime_ = m.uptime_ticks;
      speed_at_ = now;
    } else if (const double wall_s = std::chrono::duration<double>(now - speed_at_).count();
               info_ && info_->tick_hz != 0 && wall_s >= 0.05) {
      const double dev_s = (m.uptime_ticks - speed_uptime_) / static_cast<double>(info_->tick_hz);
      device_speed_ = std::clamp(dev_s / wall_s, 0.01, 1e5);
      speed_uptime_ = m.uptime_ticks;
      speed_at_ = now;
    }
    have_uptime_ = true;
    last_uptime_ = m.uptime_ticks;
    if (need_info_) unnamed_boot_ = m.boot_count;
    // Idle while recording: but only a STATUS the device sent after it acknowledged START
    // (one sent just before is still on its way when the run has begun).
    const bool after_start =
        start_ack_seq_ &&
        static_cast<std::int16_t>(static_cast<std::uint16_t>(f.seq - *start_ack_seq_)) > 0;
    if (recording_ && !stopping_ && after_start &&
        m.state == static_cast<std::uint8_t>(p::device_state::idle))
      device_idle_ = true;
    return note_lost(window_.give_up_older(m.history_oldest, 80));
  }
  return ok();
}

// Reads what arrives within `timeout_ms`; stores every new valid frame of the identified board.
status session::pump(int timeout_ms) {
  std::uint8_t in[4096];
  auto got = port_->read(in, sizeof in, timeout_ms);
  if (!got) {
    link_down_ = true;
    return got.err();
  }
  if (*got != 0) last_byte_ = steady::now();
  for (std::size_t i = 0; i < *got && !fatal_; ++i) {
    if (!info_) static_cast<void>(old_dec_.push(in[i]));  // a v1 device's frames, counted
    if (!dec_.push(in[i])) {
      // A damaged frame whose header still reads: how far past the highest number heard it
      // claims to be (a frame of this boot the line lost, if a reset follows).
      std::uint8_t type = 0;
      std::uint16_t seq = 0;
      p::status why = p::status::ok;
      if (dec_.frames().take_bad_header(&type, &seq, &why) && identified_ && window_.started()) {
        const std::int32_t d = window_.distance(seq);
        if (d > 0 && d <= 64) damaged_ahead_ = std::max(damaged_ahead_, d);
      }
      continue;
    }
    const auto& f = dec_.current();
    p::info_msg m;
    const bool is_info = f.type == static_cast<std::uint8_t>(p::msg::info) && f.as(m);
    const bool identifying = !identified_;
    if (identifying) {
      // Before the board is named, nothing of the line is stored or believed: a frame of another
      // board with the same boot count would pass for ours.
      if (!is_info) continue;
      if (!info_) {  // the handshake: run() checks it and names the session's board
        if (waiting_info_) got_info_ = m;
        waiting_info_ = false;
        continue;
      }
      if (auto s = identify(m); !s) return s;
      if (fatal_) return ok();
    } else if (is_info && m.serial != info_->serial) {
      if (auto s = identify(m); !s) return s;  // refused: another board
      return ok();
    }
    if (says_reset(f, identifying))
      if (auto s = note_reset(); !s) return s;
    const std::int32_t ahead = window_.started() ? window_.distance(f.seq) : 0;
    const auto arrived = window_.arrive(f.seq);
    if (arrived == receive_window::arrival::recovered) ++recovered_;
    if (arrived == receive_window::arrival::fresh) {
      last_fresh_ = steady::now();
      if (!have_rate_) {
        have_rate_ = true;
        rate_at_ = last_fresh_;
        rate_seq_ = window_.highest();
      }
      since_link_loss_ = false;
      damaged_ahead_ = std::max(0, damaged_ahead_ - std::max(0, ahead));
      // Only a new highest frame says the damaged ones before it were no later frames of this
      // boot: one sent again (RESEND) after them does not (review of issue 32: a DWELL damaged
      // just before a reset, then an older frame resent, and the reset's GAP counted nothing).
      bad_at_last_good_ = dec_.counts().bad();
    }
    if (is_info) {
      if (auto s = on_info(f, m); !s) return s;
      continue;
    }
    if (arrived != receive_window::arrival::repeat)
      if (auto s = append_frame(f); !s) return s;
    // A STATUS says something now even when its number looks old.
    if (arrived != receive_window::arrival::repeat ||
        f.type == static_cast<std::uint8_t>(p::msg::status))
      if (auto s = on_frame(f); !s) return s;
  }
  if (identified_) return note_corrupt();
  return ok();
}

// RESEND for what is missing and due (receive_window::due); nothing while the line is silent.
status session::request_missing() {
  if (line_silent()) return ok();
  for (;;) {
    const auto due = window_.due(resend_interval_s(), p::resend_msg::max_seqs);
    if (due.empty()) return ok();
    p::resend_msg m;
    m.count = static_cast<std::uint8_t>(due.size());
    std::copy(due.begin(), due.end(), m.seqs);
    if (auto s = send(m, seq_++); !s) return s;
  }
}

// What the recorder does between reads: RESEND what is missing, and probe a quiet device.
status session::keep_up() {
  if (!identified_) return ok();
  if (auto s = request_missing(); !s) return s;
  return probe();
}

// Nothing new for longer than the device's STATUS period: a burst of losses, or frames lost
// with none after them yet (the recorder learns of a loss only from a later frame). A RESEND
// of the numbers after the highest seen brings back what the device holds, GONE names what it
// no longer has, and numbers it has not sent are ignored (docs/PROTOCOL.md, RESEND).
status session::probe() {
  if (!window_.started()) return ok();
  const double period_s = running_.status_period_ms != 0 ? running_.status_period_ms / 1e3 : 1.0;
  const auto now = steady::now();
  const auto since = [&](steady::time_point t) {
    return std::chrono::duration<double>(now - t).count() * device_speed_;
  };
  // At least 10 ms of ours too: an emulator flat out would otherwise be "quiet" while this
  // process merely waits for the disk. A silent line is probed at most every 0.5 s of ours (a
  // stopped emulator is not flooded).
  const bool quiet =
      since(last_fresh_) >= 1.2 * period_s && now - last_fresh_ >= std::chrono::milliseconds(10);
  if (!quiet || since(last_probe_) < 0.3) return ok();
  if (line_silent() && now - last_probe_ < std::chrono::milliseconds(500)) return ok();
  last_probe_ = now;
  p::resend_msg m;
  m.count = 4;
  for (std::uint8_t i = 0; i < m.count; ++i)
    m.seqs[i] = static_cast<std::uint16_t>(window_.next() + i);
  return send(m, seq_++);
}

// The end of a run: what is still missing is asked for until it comes or the time is up; the
// rest is lost.
status session::drain_missing() {
  const auto until = steady::now() + std::chrono::duration<double>(c_.drain_s);
  while (window_.missing() != 0 && steady::now() < until && port_) {
    if (auto s = request_missing(); !s) break;
    if (auto s = pump(50); !s) break;
  }
  return note_lost(window_.give_up_all());
}

// PING until an INFO comes. A device that answers (valid frames arrive) but whose INFO the line
// keeps damaging is asked up to 100 times (the 81-byte INFO arrives whole 13 % of the time at a
// bit error rate of 2e-2: 12 tries fail one time in five, 100 one time in a million); a try ends
// early when a damaged frame came after the PING (its INFO, most likely). Nothing valid at all:
// 12 tries. A device of protocol version 1 is told by its frames as v1 framed them (no line
// code): three of them agreeing on a version, and no frame of ours.
result<p::info_msg> session::ping() {
  constexpr int quiet_attempts = 12;
  constexpr int answering_attempts = 100;
  const std::uint32_t good_before = dec_.counts().good;
  const std::uint64_t bytes_before = dec_.line().corrected + dec_.line().uncorrectable;
  const double wait_s = ping_wait_s();
  // A stopped or slow peer is not a dead line: the PINGs go on for as long, in wall time, as 12
  // take at the rig's own clock (12 x reply_timeout_s / 4: 6 s), also when the device's clock
  // runs faster (second review of issue 32: at an emulator's 50x the 12 tries took 0.6 s, and an
  // emulator stopped for 3 s just after a reset ended the run). Past the quick tries a PING goes
  // every 0.5 s at most, as keep_up()'s probe of a silent line (a stopped device is not flooded).
  const auto t0 = steady::now();
  const auto patience = std::chrono::duration<double>(quiet_attempts * c_.reply_timeout_s / 4);
  int k = 0;
  for (; k < (dec_.counts().good != good_before ? answering_attempts : quiet_attempts) ||
         steady::now() - t0 < patience;
       ++k) {
    if (stop_) return interrupted();
    got_info_.reset();
    waiting_info_ = true;
    if (auto s = send(p::ping_msg{}, seq_++); !s) return s.err();
    const auto sent = steady::now();
    const double try_s = k < quiet_attempts ? wait_s : std::max(wait_s, 0.5);
    const auto until = sent + std::chrono::duration<double>(try_s);
    const std::uint32_t bad_at_send = dec_.counts().bad();
    while (!got_info_ && steady::now() < until) {
      if (stop_) return interrupted();
      if (disk_error_) return *disk_error_;
      if (auto s = pump(std::clamp(static_cast<int>(wait_s * 1e3 / 5), 1, 20)); !s) return s.err();
      if (fatal_) return *fatal_;
      if (old_dec_.counts().bad_version >= 3 && dec_.counts().good == good_before)
        return foreign_protocol(c_.port, old_dec_.counts().foreign_version);
      if (dec_.counts().bad() != bad_at_send &&
          steady::now() - sent >= std::chrono::duration<double>(std::min(wait_s, 0.05)))
        break;  // damaged on the way: ask again now
    }
    if (got_info_) break;
  }
  waiting_info_ = false;
  if (got_info_) return *got_info_;
  const double waited = std::chrono::duration<double>(steady::now() - t0).count();
  if (dec_.counts().bad() != 0 || dec_.line().uncorrectable != 0 ||
      dec_.line().corrected + dec_.line().uncorrectable != bytes_before)
    return runtime_error(fmt::format(
        "{}: bytes arrive but no valid reply to {} PINGs came within {:.3g} s ({} damaged "
        "frames): a wrong baud rate, a very noisy line, or not a gyroflip rig",
        c_.port, k, waited, dec_.counts().bad()));
  return runtime_error(fmt::format(
      "{}: no reply to PING within {:.3g} s (nothing arrived): is the rig connected, powered and "
      "running its firmware?",
      c_.port, waited));
}

// Sends a command until the device answers it. Every try carries the same sequence number (the
// command's id): the device executes it once and acknowledges each try; a NAK saying it arrived
// damaged makes the next try go at once. A reset seen meanwhile ends it (restart_): a command
// retried after a reset is not the same command; the caller homes, configures and starts again.
template <class M>
status session::command(const M& m, const char* name, on_ack then) {
  constexpr int attempts = 8;
  const std::uint16_t id = seq_++;
  restart_ = false;
  replied_ = false;
  reply_nak_.reset();
  reply_seq_ = id;
  reply_type_ = static_cast<std::uint8_t>(M::type);
  reply_epoch_ = epoch_;
  reply_then_ = then;
  const auto done = [&] { reply_seq_.reset(); };
  for (int k = 0; k < attempts && !replied_; ++k) {
    resend_now_ = false;
    if (auto s = send(m, id); !s) return done(), s;
    const auto until = steady::now() + std::chrono::duration<double>(c_.reply_timeout_s / 4);
    while (!replied_ && !resend_now_ && steady::now() < until) {
      // Ctrl-C while starting a run ends it at once (the STOP that ends a run is not cut short).
      if (stop_ && !stopping_) return done(), interrupted();
      if (disk_error_ && !stopping_) return done(), *disk_error_;
      if (auto s = pump(read_wait_ms()); !s) return done(), s;
      if (fatal_) return done(), *fatal_;
      if (epoch_ != reply_epoch_) {
        restart_ = true;
        done();
        return runtime_error(
            fmt::format("{}: the device restarted while {} waited for its answer", c_.port, name));
      }
      // The run may already be going (a START whose ACK was lost): what is lost meanwhile is
      // asked for now, while the device still has it.
      if (auto s = keep_up(); !s) return done(), s;
      // ... and it may hold the whole --duration before an ACK comes (8 tries of 0.5 s are 200 s
      // of an emulator at 50x): the run ends at its duration, not after the last try (review of
      // issue 32: 75.9 s stored for --duration 60 with START's replies lost on a BER 1e-2 line).
      // start_run() writes the START record the device's frames prove.
      if (start_in_flight_ && run_evidence_ && c_.duration_s > 0 && data_s() >= c_.duration_s)
        return done(), runtime_error(fmt::format("{}: the duration was recorded while {} waited "
                                                 "for its answer",
                                                 c_.port, name));
    }
  }
  done();
  if (!replied_)
    return runtime_error(fmt::format("{}: the device did not acknowledge {} within {:g} s", c_.port,
                                     name, 2 * c_.reply_timeout_s));
  if constexpr (std::is_same_v<M, p::configure_msg>) {
    if (reply_nak_)
      return input_error({c_.port},
                         fmt::format("the device refused {}: {}", name,
                                     configure_refusal(m, info_ ? &*info_ : nullptr, *reply_nak_)));
  }
  if (reply_nak_)
    return input_error({c_.port},
                       fmt::format("the device refused {}: {}", name, status_name(*reply_nak_)));
  return ok();
}

// STOP (a run left from before), CONFIGURE, START naming that configuration; each stored once the
// device agreed (on_frame). After a reset the table is homed first: the rebooted firmware counts
// its steps from wherever the table stands.
status session::start_run() {
  close_segment();  // the dwells from here on are the new run's
  recording_ = false;
  device_idle_ = false;
  if (reset_seen_) running_.flags |= p::cfg_home;
  reset_seen_ = false;
  configured_at_.reset();
  if (auto s = command(p::stop_msg{}, "STOP"); !s) return s;
  if (auto s = command(running_, "CONFIGURE", on_ack::configure); !s) return s;
  p::start_msg start;
  start.config_crc = p::configure_crc(running_);
  start_ack_seq_.reset();
  start_in_flight_ = true;
  run_evidence_ = false;
  auto s = command(start, "START", on_ack::start);
  start_in_flight_ = false;
  // No ACK came through, but the device shows the run: the START began it.
  if (!s && !restart_ && !reply_nak_ && run_evidence_ && configured_at_ && !recording_)
    return begin_recording(*configured_at_, start.config_crc);
  return s;
}

// START was acknowledged by the device's frame `ack_seq` (or its run began after this boot's
// CONFIGURE, number `ack_seq`): the boot's frames after that one are the new run's (the START
// record says so; frames that came before the record are stored already).
status session::begin_recording(std::uint16_t ack_seq, std::uint16_t config_crc) {
  std::uint8_t b[4];
  p::writer w{b, sizeof b};  // little-endian, as every record body
  w.u16(ack_seq);
  w.u16(config_crc);
  if (auto s = append(gfr::kind::start, b); !s) return s;
  recording_ = true;
  ever_started_ = true;
  start_ack_seq_ = ack_seq;
  start_in_flight_ = false;
  device_idle_ = false;
  return ok();
}

// The device rebooted (its INFO said so, or its STATUS went idle or back in time, or a frame
// came from another boot): what it still owed is lost, the run goes on after a homing and the
// same configuration. A device that went idle in the same boot is only started again.
status session::handle_reset() {
  if (need_info_ || (!reset_seen_ && device_idle_)) {
    // The reset's INFO was lost; or an idle device, rebooted (its INFO and STATUS lost) or
    // stopped by itself. Its INFO tells which.
    auto info = ping();
    if (!info) return info.err();
    if (!reset_seen_) device_idle_ = false;  // same boot: it only stopped; start it again
  }
  if (auto s = note_lost(window_.give_up_all()); !s) return s;
  return start_run();
}

result<recorder_result> session::finish(gfr::stop_reason why) {
  stopping_ = true;
  if (port_ && why != gfr::stop_reason::link_lost) {
    // STOP, then the STATUS that answers it, and what the device still owes us.
    (void)command(p::stop_msg{}, "STOP");
    (void)drain_missing();
    (void)pump(100);
    // A number skipped by the last frames read is lost too: counted (it used to be in no GAP).
    (void)note_lost(window_.give_up_all());
  } else {
    (void)note_lost(window_.give_up_all());
  }
  if (disk_error_) return end_disk_full();  // the file took no more meanwhile
  if (auto s = close_file(why); !s) return s.err();
  recorder_result r;
  r.reason = why;
  // The harmonic scheme holds its last visiting period back until it knows the run goes on: the
  // run's end is known now (calibrate of the file takes it too). The 0/180 cycles as before.
  if (stream_.demod().dwell_per_row())
    stream_.flush([this](const method::cycle& cy) { cycles_.push_back(cy); });
  look(true);
  r.last = status_now();
  if (on_progress_) on_progress_(r.last);
  return r;
}

// The port failed (an unplugged adapter): keep the file, wait for the device path to come back,
// name the board on it before anything of it is stored, and go on where the device is; a device
// that rebooted meanwhile is started again, another one is refused. False: the port did not come
// back in time, or a stop was asked for meanwhile.
result<bool> session::reconnect(steady::time_point lost_at) {
  port_.reset();
  identified_ = false;
  waiting_for_port_ = true;
  since_link_loss_ = true;
  lost_at_ = lost_at;
  const auto until = lost_at + std::chrono::duration<double>(c_.reconnect_timeout_s);
  while (steady::now() < until && !stop_) {
    if (auto s = tick(); !s) return s.err();
    if (disk_error_) return true;  // the main loop ends the run
    std::this_thread::sleep_for(std::chrono::duration<double>(port_poll_s()));
    if (!open_port()) continue;
    link_down_ = false;
    auto info = ping();        // identifies the board (pump): the link-lost GAP, then its INFO
    if (fatal_) return false;  // another board: the main loop closes the file with the reason
    if (disk_error_) return true;
    if (!info) {
      if (!link_down_ && info.err().code == errc::bad_input) return info.err();
      port_.reset();
      continue;
    }
    if (!reset_seen_ && !need_info_ && info->config == running_ && !device_idle_) {
      // What the device sent meanwhile is asked for now: its history is device time, and at an
      // emulator's 50x the few ms of a round trip count.
      (void)request_missing();
      return true;
    }
    if (auto s = handle_reset(); !s) {
      if (fatal_) return false;
      if (disk_error_) return true;
      if (!link_down_ && !restart_) return s.err();
      if (restart_) return true;  // another reset meanwhile: the main loop starts again
      port_.reset();
      identified_ = false;
      lost_at_ = steady::now();
      waiting_for_port_ = true;
      continue;
    }
    return true;
  }
  waiting_for_port_ = false;
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(steady::now() - lost_at_);
  if (auto s = append_gap(gfr::gap_reason::link_lost, static_cast<std::uint32_t>(ms.count())); !s)
    return s.err();
  return false;
}

result<recorder_result> session::run() {
  if (auto s = append(gfr::kind::meta,
                      [&] {
                        const auto m = meta_json(c_);
                        return std::vector<std::uint8_t>(m.begin(), m.end());
                      }());
      !s)
    return s.err();
  if (disk_error_) return *disk_error_;  // full from the start: record() removes the file
  if (auto s = open_port(); !s) return s.err();
  auto info = ping();
  if (!info) return info.err();
  if (info->protocol != p::protocol_version) return foreign_protocol(c_.port, info->protocol);
  info_ = *info;
  identified_ = true;
  if (auto s = append(gfr::kind::info, payload_of(*info)); !s) return s.err();
  bool need_start = true;
  while (true) {
    if (disk_error_) return end_disk_full();
    if (fatal_) {
      // Another device: leave it alone; close the file with its reason.
      (void)close_file(gfr::stop_reason::device_changed);
      return *fatal_;
    }
    if (stop_) return finish(gfr::stop_reason::signal);
    if (c_.duration_s > 0 && data_s() >= c_.duration_s) return finish(gfr::stop_reason::duration);
    bool lost = !port_;
    if (!lost && (need_start || reset_seen_ || device_idle_ || need_info_)) {
      link_down_ = false;
      if (auto s = need_start && !reset_seen_ && !need_info_ ? start_run() : handle_reset(); !s) {
        if (fatal_ || disk_error_) continue;
        if (link_down_) {
          lost = true;
        } else if (restart_) {
          // A reset while starting: start again, homed. A device that resets at every start
          // ends the run after 10 tries without a dwell.
          if (++restart_failures_ >= 10) {
            (void)close_file(gfr::stop_reason::device_failed);
            return s.err();
          }
          continue;
        } else if (!ever_started_) {
          return s.err();  // nothing recorded: a refused configuration, a mute device
        } else {
          // A command went unanswered (a noisy line, another reset meanwhile): try again from
          // the top, homed; after three whole attempts end the run, the file closed with its
          // reason.
          reset_seen_ = true;
          if (++restart_failures_ < 3) continue;
          (void)close_file(gfr::stop_reason::device_failed);
          return s.err();
        }
      } else {
        need_start = false;
        (void)file_.sync();
      }
    }
    if (!lost) {
      link_down_ = false;
      if (auto s = pump(read_wait_ms()); !s) {
        if (!link_down_) {  // not the line (a record the reader refused): stop the device
          (void)command(p::stop_msg{}, "STOP");
          (void)file_.close();
          return s.err();
        }
        lost = true;
      }
    }
    if (!lost) {
      if (auto s = keep_up(); !s) {
        if (!link_down_) return s.err();
        lost = true;
      }
    }
    if (lost && info_->serial == 0) return end_unserialled();
    if (lost) {
      auto back = reconnect(steady::now());
      if (!back) return back.err();
      if (fatal_ || disk_error_) continue;  // closed above, with its reason
      if (!*back) return finish(stop_ ? gfr::stop_reason::signal : gfr::stop_reason::link_lost);
    }
    if (auto t = tick(); !t) return t.err();
  }
}

}  // namespace

std::string configure_refusal(const p::configure_msg& c, const p::info_msg* device,
                              std::uint8_t reason) {
  std::string why = status_name(reason);
  if (device == nullptr || reason != static_cast<std::uint8_t>(p::status::bad_arg)) return why;
  if (p::check_configure(c, device->mclk_hz) != p::status::ok) return why;
  // What the board itself cannot do (device::configure: board_facts::max_step_rate_sps and the
  // step timer's 16 bits).
  if (device->board == static_cast<std::uint8_t>(p::board_kind::hardware) &&
      c.step_rate_sps > fw::msp430f149::max_step_rate_sps)
    return fmt::format(
        "{}: the top step rate {} steps/s is above the {} steps/s an MSP430F149 board produces "
        "(--step-rate; docs/FIRMWARE.md, \"Rates the board can produce\")",
        why, c.step_rate_sps, fw::msp430f149::max_step_rate_sps);
  if (c.start_rate_sps != 0 && device->tick_hz / c.start_rate_sps > 0xFFFFu)
    return fmt::format(
        "{}: the start rate {} steps/s is below the {} steps/s the board's 16-bit step timer "
        "times at {} ticks/s (--start-rate)",
        why, c.start_rate_sps, device->tick_hz / 0xFFFFu + 1, device->tick_hz);
  return why;
}

method::pairing live_pairing(const position_table& table) noexcept {
  return table.size() >= 3 ? method::pairing::harmonic : method::pairing::abba;
}

result<recorder_result> record(const recorder_config& cfg, const std::atomic<bool>& stop,
                               const recorder_progress_fn& on_progress) {
  if (auto s = cfg.rig.check(); !s) return s.err();  // before the file or the port
  // The port's name, held until the end, also while the port is gone: a second recorder is
  // refused before it makes a file.
  auto lock = port_lock::of_name(cfg.port);
  if (!lock) return lock.err();
  auto w = gfr::writer::create(cfg.output);
  if (!w) return w.err();
  auto r = session(cfg, std::move(*w), std::move(*lock), stop, on_progress).run();
  // Nothing recorded yet (no reply, another protocol, a refused configuration, a full disk at
  // the start): no file. A file that holds a run, or a dwell of one, is kept.
  if (!r) {
    auto f = gfr::read(cfg.output);
    const bool started = f && std::any_of(f->records.begin(), f->records.end(), [](auto& x) {
                           return x.type == gfr::kind::start ||
                                  (x.type == gfr::kind::frame && !x.body.empty() &&
                                   x.body[0] == static_cast<std::uint8_t>(p::msg::dwell));
                         });
    if (!started) std::remove(cfg.output.c_str());
  }
  return r;
}

}  // namespace gyroflip::host
