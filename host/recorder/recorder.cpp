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
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/status.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/method/flip_stream.hpp"
#include "host/serial/serial_port.hpp"

namespace gyroflip::host {

namespace {

using steady = std::chrono::steady_clock;
namespace p = protocol;

const char* status_name(std::uint8_t s) {
  switch (static_cast<p::status>(s)) {
    case p::status::ok:
      return "ok";
    case p::status::bad_arg:
      return "a value out of range";
    case p::status::bad_frame:
      return "a malformed frame";
    case p::status::crc_mismatch:
      return "a CRC mismatch";
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

class session {
 public:
  session(const recorder_config& c, gfr::writer w, const std::atomic<bool>& stop,
          const recorder_progress_fn& fn)
      : c_(c), file_(std::move(w)), stop_(stop), on_progress_(fn), live_(c.output, false) {}

  result<recorder_result> run();

 private:
  // The link.
  status open_port();
  template <class M>
  status send(const M& m, std::uint16_t* seq_out = nullptr);
  status pump(int timeout_ms);
  status on_frame(const p::frame& f);
  result<p::info_msg> ping();
  template <class M>
  status command(const M& m, const char* name);
  status start_run();
  status begin_recording();
  result<bool> reconnect(steady::time_point lost_at);
  result<recorder_result> finish(gfr::stop_reason why);
  // The file.
  status append(gfr::kind k, std::span<const std::uint8_t> body = {});
  status append_gap(gfr::gap_reason r, std::uint32_t count);
  status note_decoder();
  status tick();
  [[nodiscard]] recorder_status status_now() const;
  [[nodiscard]] double elapsed_s() const {
    const auto& d = live_.run().dwells;
    return d.empty() ? 0.0 : d.back().time_s;
  }
  [[nodiscard]] std::uint64_t host_us() const {
    return static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::microseconds>(steady::now() - t0_).count());
  }

  // A rebooted firmware counts the table's steps from where it stands: unless it finds the home
  // switch first, a reset while the table was at B would name every later B dwell A.
  void home_after_reset() { running_.flags |= p::cfg_home; }

  const recorder_config& c_;
  p::configure_msg running_ = c_.device;  // what the device runs with (CONFIGURE records)
  gfr::writer file_;
  const std::atomic<bool>& stop_;
  const recorder_progress_fn& on_progress_;
  rig_run_builder live_;
  std::size_t records_ = 0;
  method::flip_stream stream_{method::pairing::abba};
  std::vector<method::cycle> cycles_;
  std::size_t dwells_seen_ = 0;

  std::optional<serial_port> port_;
  p::frame_decoder dec_{true};  // a device reset restarts its numbering: take repeats too
  std::uint32_t noted_bad_ = 0, noted_missing_ = 0;
  std::uint16_t seq_ = 0;
  bool recording_ = false;      // after START: every frame goes to the file
  bool start_pending_ = false;  // a START was sent: its ACK begins the recording
  bool stopping_ = false;
  bool waiting_info_ = false;
  std::optional<p::info_msg> info_;                      // the INFO a PING brought
  std::optional<std::vector<std::uint8_t>> reset_info_;  // an unasked INFO (the device rebooted)
  bool device_idle_ = false;                             // a STATUS said idle while we record
  std::optional<std::uint16_t> reply_seq_;
  std::optional<std::uint8_t> reply_nak_;  // reason, when the reply was a NAK
  bool replied_ = false;
  bool waiting_for_port_ = false;
  bool link_down_ = false;  // the last error came from the port, not the file
  steady::time_point t0_ = steady::now();
  steady::time_point last_tick_ = steady::now();
};

status session::append(gfr::kind k, std::span<const std::uint8_t> body) {
  gfr::record r{k, host_us(), {body.begin(), body.end()}};
  if (auto s = file_.append(k, r.host_time_us, body); !s) return s;
  if (auto s = live_.add(r, ++records_); !s) return s;
  const auto& dw = live_.run().dwells;
  for (; dwells_seen_ < dw.size(); ++dwells_seen_)
    if (auto row = dwell_row(dw[dwells_seen_]))
      stream_.push(*row, [this](const method::cycle& cy) { cycles_.push_back(cy); });
  return ok();
}

status session::append_gap(gfr::gap_reason r, std::uint32_t count) {
  std::uint8_t b[5];
  p::writer w{b, sizeof b};
  w.u8(static_cast<std::uint8_t>(r));
  w.u32(count);
  return append(gfr::kind::gap, b);
}

// Frames the decoder dropped or found missing since the last call become gap records.
status session::note_decoder() {
  const auto& k = dec_.counts();
  if (k.bad() != noted_bad_) {
    if (auto s = append_gap(gfr::gap_reason::corrupt, k.bad() - noted_bad_); !s) return s;
    noted_bad_ = k.bad();
  }
  if (k.missing != noted_missing_) {
    if (auto s = append_gap(gfr::gap_reason::missing, k.missing - noted_missing_); !s) return s;
    noted_missing_ = k.missing;
  }
  return ok();
}

// What the run looks like now (the progress report and the result).
recorder_status session::status_now() const {
  recorder_status st;
  const auto& run = live_.run();
  st.elapsed_s = elapsed_s();
  st.duration_s = c_.duration_s;
  st.dwells = run.dwells.size();
  st.cycles = cycles_.size();
  st.frames_good = run.frames;
  st.frames_corrupt = run.corrupt_frames;
  st.frames_missing = run.missing_frames;
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
  return st;
}

// About once a second: sync the file (what was acknowledged survives a power loss) and report.
status session::tick() {
  const auto now = steady::now();
  if (now - last_tick_ < std::chrono::seconds(1)) return ok();
  last_tick_ = now;
  if (auto s = file_.sync(); !s) return s;
  if (on_progress_) on_progress_(status_now());
  return ok();
}

status session::open_port() {
  auto port = serial_port::open(c_.port, c_.baud);
  if (!port) return port.err();
  port_.emplace(std::move(*port));
  return ok();
}

template <class M>
status session::send(const M& m, std::uint16_t* seq_out) {
  std::uint8_t buf[p::max_wire];
  const std::uint16_t seq = seq_++;
  const std::size_t n = p::encode_message(m, seq, buf, sizeof buf);
  if (seq_out != nullptr) *seq_out = seq;
  auto s = port_->write(buf, n, 1000);
  if (!s) link_down_ = true;
  return s;
}

status session::on_frame(const p::frame& f) {
  const auto type = static_cast<p::msg>(f.type);
  if ((type == p::msg::ack || type == p::msg::nak) && reply_seq_) {
    p::ack_msg a;
    p::nak_msg n;
    if (f.as(a) && a.seq == *reply_seq_) replied_ = true;
    // Any START's ACK: a retried START's first ACK may be the one that got through.
    if (start_pending_ && f.as(a) && a.of_type == static_cast<std::uint8_t>(p::msg::start)) {
      replied_ = true;
      if (auto s = begin_recording(); !s) return s;
    }
    if (f.as(n) && n.seq == *reply_seq_) {
      replied_ = true;
      reply_nak_ = n.reason;
    }
  }
  if (type == p::msg::info) {
    p::info_msg m;
    if (!f.as(m)) return ok();
    if (waiting_info_) {
      info_ = m;
      waiting_info_ = false;
      return ok();
    }
    // An INFO nobody asked for: the device booted again (docs/PROTOCOL.md, INFO).
    if (recording_) reset_info_.emplace(f.payload, f.payload + f.length);
    return ok();
  }
  if (type == p::msg::status && recording_ && !stopping_) {
    p::status_msg m;
    if (f.as(m) && m.state == static_cast<std::uint8_t>(p::device_state::idle)) device_idle_ = true;
  }
  return ok();
}

// Reads what arrives within `timeout_ms`; stores every valid frame while recording.
status session::pump(int timeout_ms) {
  std::uint8_t in[4096];
  auto got = port_->read(in, sizeof in, timeout_ms);
  if (!got) {
    link_down_ = true;
    return got.err();
  }
  for (std::size_t i = 0; i < *got; ++i) {
    if (!dec_.push(in[i])) continue;
    const auto& f = dec_.current();
    if (recording_) {
      std::uint8_t body[3 + p::max_payload];
      p::writer w{body, sizeof body};
      w.u8(f.type);
      w.u16(f.seq);
      std::copy_n(f.payload, f.length, w.take(f.length));
      if (auto s = append(gfr::kind::frame, {body, w.n}); !s) return s;
    }
    if (auto s = on_frame(f); !s) return s;
  }
  if (recording_) return note_decoder();
  return ok();
}

// PING until an INFO comes (a noisy line may take several tries). A device of another protocol
// version is told by the version byte of the frames the decoder drops: only when three of them
// agree and no frame of ours came (a bit flip in a frame's first byte looks the same, and a noisy
// line still lets some frames through).
result<p::info_msg> session::ping() {
  constexpr int attempts = 6;
  std::map<std::uint8_t, int> foreign;
  std::uint32_t seen_bad_version = dec_.counts().bad_version;
  const std::uint32_t good_before = dec_.counts().good;
  for (int k = 0; k < attempts && !stop_; ++k) {
    info_.reset();
    waiting_info_ = true;
    if (auto s = send(p::ping_msg{}); !s) return s.err();
    const auto until = steady::now() + std::chrono::duration<double>(c_.reply_timeout_s / 3);
    while (!info_ && steady::now() < until && !stop_) {
      if (auto s = pump(20); !s) return s.err();
      if (dec_.counts().bad_version != seen_bad_version) {
        seen_bad_version = dec_.counts().bad_version;
        if (++foreign[dec_.counts().foreign_version] >= 3 && dec_.counts().good == good_before) {
          waiting_info_ = false;
          return foreign_protocol(c_.port, dec_.counts().foreign_version);
        }
      }
    }
    if (info_) break;
  }
  waiting_info_ = false;
  if (info_) return *info_;
  return runtime_error(
      fmt::format("{}: no reply to PING within {:g} s: is the rig connected, "
                  "powered and running its firmware?",
                  c_.port, attempts * c_.reply_timeout_s / 3));
}

// Sends a command until the device answers it: a frame lost on a noisy line (the command, or its
// ACK) is sent again with a new sequence number. Every command the recorder sends is idempotent
// (STOP, CONFIGURE while idle, START while running: docs/PROTOCOL.md).
template <class M>
status session::command(const M& m, const char* name) {
  constexpr int attempts = 4;
  replied_ = false;
  for (int k = 0; k < attempts && !replied_; ++k) {
    std::uint16_t seq = 0;
    reply_nak_.reset();
    if (auto s = send(m, &seq); !s) return s;
    reply_seq_ = seq;
    const auto until = steady::now() + std::chrono::duration<double>(c_.reply_timeout_s / attempts);
    while (!replied_ && steady::now() < until)
      if (auto s = pump(20); !s) return s;
    reply_seq_.reset();
  }
  if (!replied_)
    return runtime_error(fmt::format("{}: the device did not acknowledge {} within {:g} s", c_.port,
                                     name, c_.reply_timeout_s));
  if (reply_nak_)
    return input_error({c_.port},
                       fmt::format("the device refused {}: {}", name, status_name(*reply_nak_)));
  return ok();
}

// STOP (a run left from before), CONFIGURE, START; each step stored once the device agreed.
status session::start_run() {
  recording_ = false;
  if (auto s = command(p::stop_msg{}, "STOP"); !s) return s;
  if (auto s = command(running_, "CONFIGURE"); !s) return s;
  if (auto s = append(gfr::kind::configure, payload_of(running_)); !s) return s;
  start_pending_ = true;
  auto s = command(p::start_msg{}, "START");
  start_pending_ = false;
  return s;
}

// The device's ACK of START: from the next byte on, every frame is the run's. The device may send
// its first DWELLs right behind the ACK, in the same read: they must not pass unstored.
status session::begin_recording() {
  if (auto s = append(gfr::kind::start); !s) return s;
  start_pending_ = false;
  device_idle_ = false;
  recording_ = true;
  // Gap records count what is lost while recording, not the handshake's noise.
  noted_bad_ = dec_.counts().bad();
  noted_missing_ = dec_.counts().missing;
  return ok();
}

result<recorder_result> session::finish(gfr::stop_reason why) {
  stopping_ = true;
  if (port_ && why != gfr::stop_reason::link_lost) {
    // STOP, then the STATUS that answers it; a device that does not answer is noted only.
    (void)command(p::stop_msg{}, "STOP");
    (void)pump(100);
  }
  const std::uint8_t body[1] = {static_cast<std::uint8_t>(why)};
  if (auto s = append(gfr::kind::stop, body); !s) return s.err();
  if (auto s = file_.close(); !s) return s.err();  // syncs
  recorder_result r;
  r.reason = why;
  r.last = status_now();
  if (on_progress_) on_progress_(r.last);
  return r;
}

// The port failed (an unplugged adapter): keep the file, wait for the device path to come back,
// and go on where the device is; a device found reconfigured (it rebooted) is started again.
// False: the port did not come back in time, or a stop was asked for meanwhile.
result<bool> session::reconnect(steady::time_point lost_at) {
  port_.reset();
  waiting_for_port_ = true;
  const auto until = lost_at + std::chrono::duration<double>(c_.reconnect_timeout_s);
  const auto gap = [&]() {
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(steady::now() - lost_at);
    return append_gap(gfr::gap_reason::link_lost, static_cast<std::uint32_t>(ms.count()));
  };
  while (steady::now() < until && !stop_) {
    if (auto s = tick(); !s) return s.err();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    if (!open_port()) continue;
    link_down_ = false;
    auto info = ping();
    if (!info) {
      if (!link_down_ && info.err().code == errc::bad_input) return info.err();
      port_.reset();
      continue;
    }
    waiting_for_port_ = false;
    if (auto s = gap(); !s) return s.err();
    if (info->config == running_) return true;
    if (auto s = append_gap(gfr::gap_reason::device_reset, 0); !s) return s.err();
    if (auto s = append(gfr::kind::info, payload_of(*info)); !s) return s.err();
    home_after_reset();
    if (auto s = start_run(); !s) {
      if (!link_down_) return s.err();
      port_.reset();
      lost_at = steady::now();
      waiting_for_port_ = true;
      continue;
    }
    return true;
  }
  waiting_for_port_ = false;
  if (auto s = gap(); !s) return s.err();
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
  if (auto s = open_port(); !s) return s.err();
  auto info = ping();
  if (!info) return info.err();
  if (info->protocol != p::protocol_version) return foreign_protocol(c_.port, info->protocol);
  if (auto s = append(gfr::kind::info, payload_of(*info)); !s) return s.err();
  if (auto s = start_run(); !s) return s.err();
  (void)file_.sync();
  while (true) {
    if (stop_) return finish(gfr::stop_reason::signal);
    if (c_.duration_s > 0 && elapsed_s() >= c_.duration_s)
      return finish(gfr::stop_reason::duration);
    bool lost = !port_;
    if (!lost && (reset_info_ || device_idle_)) {
      // The device rebooted (an unasked INFO) or stopped by itself: note it and start it again.
      if (auto s = append_gap(gfr::gap_reason::device_reset, 0); !s) return s.err();
      if (reset_info_)
        if (auto s = append(gfr::kind::info, *reset_info_); !s) return s.err();
      reset_info_.reset();
      link_down_ = false;
      home_after_reset();
      if (auto s = start_run(); !s) {
        if (!link_down_) return s.err();
        lost = true;
      }
    }
    if (!lost) {
      link_down_ = false;
      if (auto s = pump(100); !s) {
        if (!link_down_) return s.err();  // the file failed
        lost = true;
      }
    }
    if (lost) {
      auto back = reconnect(steady::now());
      if (!back) return back.err();
      if (!*back) return finish(stop_ ? gfr::stop_reason::signal : gfr::stop_reason::link_lost);
    }
    if (auto t = tick(); !t) return t.err();
  }
}

}  // namespace

result<recorder_result> record(const recorder_config& cfg, const std::atomic<bool>& stop,
                               const recorder_progress_fn& on_progress) {
  auto w = gfr::writer::create(cfg.output);
  if (!w) return w.err();
  auto r = session(cfg, std::move(*w), stop, on_progress).run();
  // Nothing recorded yet (no reply, another protocol, a refused configuration): no file.
  if (!r) {
    auto f = gfr::read(cfg.output);
    const bool started = f && std::any_of(f->records.begin(), f->records.end(),
                                          [](auto& x) { return x.type == gfr::kind::start; });
    if (!started) std::remove(cfg.output.c_str());
  }
  return r;
}

}  // namespace gyroflip::host
