/// \file
/// \brief `gyroflip emulate` (docs/EMULATOR.md): the firmware core and the simulated rig behind
/// a pseudo-terminal or a serial device, paced to real time or run as fast as the reader takes.
#include "cmd_emulate.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <thread>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/finite_output.hpp"
#include "host/emulator/emulator.hpp"
#include "host/emulator/link_faults.hpp"
#include "host/serial/serial_line.hpp"
#include "physics_options.hpp"
#include "rig_options.hpp"
#include "stop_signal.hpp"

namespace gyroflip::app {

namespace {

// Writes one CSV row per DWELL the device sent (before link faults): the ground truth of a run.
// Written as the run goes (a crash test reads it while the emulator runs), so it is no
// temporary-and-rename output: `check` vets the path with everything else, and `open`, which
// truncates, comes last, once nothing can refuse the run any more.
class sent_log {
 public:
  // Errors: a folder, or a new file in a folder that is missing or not writable.
  static status check(const std::string& path) {
    if (path.empty()) return ok();
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
      if (S_ISDIR(st.st_mode)) return io_error(path, "is a directory");
      if (::access(path.c_str(), W_OK) != 0)
        return io_error(path, std::string("cannot write: ") + std::strerror(errno));
      return ok();
    }
    const auto slash = path.rfind('/');
    const std::string dir = slash == std::string::npos ? "." : path.substr(0, slash + 1);
    if (::access(dir.c_str(), W_OK) != 0)
      return io_error(path, std::string("cannot create: ") + std::strerror(errno));
    return ok();
  }
  static result<sent_log> open(const std::string& path) {
    if (path.empty()) return sent_log(nullptr, path);
    // /dev/stdout, /dev/fd/N: into that descriptor (`>> session.log` appends), not re-opened.
    auto through = io::descriptor_stream(path);
    if (!through) return through.err();
    std::FILE* f = *through != nullptr ? *through : std::fopen(path.c_str(), "w");
    if (f == nullptr) return io_error(path, std::string("cannot create: ") + std::strerror(errno));
    std::fputs(
        "seq,cycle,position,t_start_ticks,t_end_ticks,n,code_sum,code_min,code_max,n_temp,"
        "temp_sum,ax_high_ticks,ax_period_ticks,ay_high_ticks,ay_period_ticks,flags,sent_time_s,"
        "hit,table_deg,boot\n",
        f);
    return sent_log(f, path);
  }
  sent_log(sent_log&& o) noexcept : f_(std::exchange(o.f_, nullptr)), path_(std::move(o.path_)) {}
  sent_log(const sent_log&) = delete;
  sent_log& operator=(const sent_log&) = delete;
  sent_log& operator=(sent_log&&) = delete;
  ~sent_log() {
    if (f_ != nullptr) std::fclose(f_);
  }
  // Rows are flushed as they are written: a reader (a crash test) sees what was sent.
  // `hit`: a fault touched the frame or the line was gone; `table_deg`: where the table truly
  // stood during the dwell: at its last conversion (emulator::table_deg_at its t_end_ticks), not
  // at the last conversion before the frame is first seen (a frame dropped from the device's full
  // transmit ring is first seen on RESEND, after the table turned on: it was logged at the next
  // dwell's angle, and bench/rig_truth.py counted a dwell labelled right as mislabelled).
  // `boot`: the firmware's boot that made the frame (1 at the first; its numbering starts again
  // at each): not the one current when it first goes out (a DWELL held in the transmitter across
  // a reset went out after it; review of issue 32, fifth pass, finding 5).
  status add(const protocol::frame& fr, double time_s, bool hit, const host::emulator& emu,
             unsigned boot) {
    protocol::dwell_msg d;
    if (f_ == nullptr || !fr.as(d)) return ok();
    const double table_deg = emu.table_deg_at(d.t_end_ticks);
    fmt::print(f_, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.6f},{},{:.4f},{}\n", fr.seq,
               d.cycle, d.position, d.t_start_ticks, d.t_end_ticks, d.n, d.code_sum, d.code_min,
               d.code_max, d.n_temp, d.temp_sum, d.ax_high_ticks, d.ax_period_ticks,
               d.ay_high_ticks, d.ay_period_ticks, d.flags, time_s, hit ? 1 : 0, table_deg, boot);
    if (std::fflush(f_) != 0 || std::ferror(f_)) return io_error(path_, "write failed");
    return ok();
  }

 private:
  sent_log(std::FILE* f, std::string path) : f_(f), path_(std::move(path)) {}
  std::FILE* f_;
  std::string path_;
};

// --truth: the terms an indexed run of this rig should find, at the run's start temperature
// (host::emulator::harmonic_truth_at), for whatever angle table the host configures: one JSON
// object, written whole (temporary and rename) before the line opens.
status write_truth(const std::string& path, const host::emulator& emu) {
  if (path.empty()) return ok();
  auto temperature = emu.config().sim.temperature;  // at() is not const
  const double temp_c = temperature.at(0.0);
  const auto t = emu.harmonic_truth_at(temp_c);
  const auto& sim = emu.config().sim;
  const nlohmann::json j{
      {"schema", "gyroflip.emulator_truth/1"},
      {"note",
       "earth(theta) + g(theta) = mean + c1 cos(theta) + s1 sin(theta) as the gyro senses them "
       "(deg/s) at the table angle theta, at temp_c; no second harmonic (c2 = s2 = 0); a "
       "harmonic calibration's c1, s1 estimate these, its b the bias plus mean; dN of a 0/180 "
       "pair is c1"},
      {"temp_c", temp_c},
      {"latitude_deg", sim.lat_deg},
      {"axis", sim.mount.azimuth_set() ? nlohmann::json(nullptr) : nlohmann::json(sim.axis)},
      {"azimuth_deg",
       sim.mount.azimuth_set() ? nlohmann::json(sim.mount.azimuth_deg) : nlohmann::json(nullptr)},
      {"table_axis", sim.table_axis.empty() ? "horizontal (default)" : sim.table_axis},
      {"tilt_mrad", sim.mount.tilt_mrad},
      {"tilt_azimuth_deg", sim.mount.tilt_azimuth_deg},
      {"c1_dps", t.c1_dps()},
      {"s1_dps", t.s1_dps()},
      {"c2_dps", 0.0},
      {"s2_dps", 0.0},
      {"mean_dps", t.mean_dps},
      {"earth_c1_dps", t.earth_c1_dps},
      {"earth_s1_dps", t.earth_s1_dps},
      {"g_c1_dps", t.g_c1_dps},
      {"g_s1_dps", t.g_s1_dps}};
  const std::string text = j.dump(2) + "\n";
  if (auto s = io::check_finite(text, path); !s) return s;
  auto f = io::atomic_file::create(path);
  if (!f) return f.err();
  f->write(text);
  return f->commit();
}

result<host::emulator_config> emulator_config_of(const emulate_options& o) {
  host::emulator_config c;
  auto preset = load_physics(o.sensor, o.temp_c, o.temp_profile, o.rate_profile, c.sim);
  if (!preset) return preset.err();
  c.sim.lat_deg = o.lat_deg;
  c.sim.axis = o.axis;
  c.sim.table_axis = o.table_axis;
  auto mount = mount_of(o.axis, o.azimuth_deg, o.tilt_mrad, o.tilt_azimuth_deg);
  if (!mount) return mount.err();
  c.sim.mount = *mount;
  c.sim.rig.filter_word = o.filter_word;
  c.sim.rig.chop = !o.no_chop;
  c.sim.rig.steps_per_rev = o.steps_per_rev;
  c.sim.power_on_before_s = o.power_on_before_s;
  auto coil = coil_heating_of(o.coil_heat);
  if (!coil) return coil.err();
  c.sim.coil = *coil;
  c.sim.seed = o.seed;
  // A board of its own: two emulators never share a serial unless told to, so a recorder that
  // finds another one on its line (a pty path reused) refuses it instead of taking it for the
  // same board rebooted (docs/RECORDER.md).
  c.serial = o.serial.value_or(0);
  while (!o.serial && c.serial == 0) c.serial = std::random_device{}();
  return c;
}

// The fastest a faulty line runs at --speed max (docs/EMULATOR.md).
constexpr double max_faulty_speed = 25.0;

// Device time against wall time at `speed` device seconds per wall second (0: no pacing). A
// stall (a busy host) is not made up in a burst: the device's time runs at most 5 ms of wall
// time ahead of its pace, and a pace that fell behind restarts from now.
class pace {
 public:
  explicit pace(double speed) : speed_(speed) {}
  int wait_ms(double device_s, std::chrono::steady_clock::time_point now) {
    if (speed_ <= 0.0) return 0;
    if (!started_ || now - due(device_s) > std::chrono::milliseconds(5)) {
      started_ = true;
      anchor_wall_ = now;
      anchor_device_s_ = device_s;
      return 0;
    }
    const auto ahead = due(device_s) - now;
    return ahead > std::chrono::steady_clock::duration::zero()
               ? static_cast<int>(
                     std::ceil(std::chrono::duration<double, std::milli>(ahead).count()))
               : 0;
  }

 private:
  [[nodiscard]] std::chrono::steady_clock::time_point due(double device_s) const {
    return anchor_wall_ +
           std::chrono::duration_cast<std::chrono::steady_clock::duration>(
               std::chrono::duration<double>((device_s - anchor_device_s_) / speed_));
  }
  double speed_;
  bool started_ = false;
  std::chrono::steady_clock::time_point anchor_wall_{};
  double anchor_device_s_ = 0.0;
};

// Sequence numbers seen since the device booted: `take` is true the first time (a number 32768
// ahead is forgotten, so the numbering may wrap).
class first_sight {
 public:
  bool take(std::uint16_t seq) {
    if (seen_[seq]) return false;
    seen_[seq] = true;
    seen_[static_cast<std::uint16_t>(seq + 0x8000u)] = false;
    return true;
  }
  void reset() { seen_.assign(seen_.size(), false); }

 private:
  std::vector<bool> seen_ = std::vector<bool>(0x10000, false);
};

// Faults of the rig and its cable, in the order they happen: firmware resets, and the line
// vanishing (an unplugged USB-serial adapter) for a while. All in device time counted from the
// first run the host started, so that a test's faults fall inside its recording whatever the
// speed (the device runs on while the line is gone, paced as before).
struct fault_plan {
  std::vector<double> reset_at_s;                 // ascending
  std::vector<std::pair<double, double>> unplug;  // (device time, device seconds), ascending
  // The emulator stops for a while of wall time right after the next frame it sends from that
  // device time on, as under SIGSTOP: it neither reads nor sends, then catches up with the wall
  // clock (a stopped or descheduled peer, not a dead line).
  std::vector<std::pair<double, double>> stall;  // (device time, wall seconds), ascending
  // The device's UART transmitter held (a stuck transmitter, a held CTS): the firmware's
  // transmit ring fills and what does not fit is dropped from the live stream, kept in its
  // history for RESEND (a frame the log first sees late, on RESEND).
  std::vector<std::pair<double, double>> tx_hold;  // (device time, device seconds), ascending
  // Faults tied to the host's commands (CMD:N, the Nth frame of that command the device takes,
  // retries counted): the reply lost, or the firmware reset just before it takes the frame. They
  // hit a moment of a session deliberately (a START whose ACK is lost and whose retry meets a
  // rebooted device) where a time would hit it by luck.
  struct command_range {
    std::uint8_t type = 0;
    unsigned first = 0, last = 0;  // the command's frames first..last the device takes
    [[nodiscard]] bool has(std::uint8_t t, unsigned k) const {
      return t == type && k >= first && k <= last;
    }
  };
  std::vector<command_range> lose_reply, reset_before;
  bool lose_boot_info = false;
};

// A command's name as the options write it (docs/PROTOCOL.md's message names).
std::optional<std::uint8_t> command_type(const std::string& name) {
  static const std::pair<const char*, protocol::msg> names[] = {
      {"ping", protocol::msg::ping},           {"configure", protocol::msg::configure},
      {"start", protocol::msg::start},         {"stop", protocol::msg::stop},
      {"home", protocol::msg::home},           {"set_delta_n", protocol::msg::set_delta_n},
      {"calibrate", protocol::msg::calibrate}, {"resend", protocol::msg::resend}};
  for (const auto& [n, t] : names)
    if (name == n) return static_cast<std::uint8_t>(t);
  return std::nullopt;
}

// CMD:N or CMD:N-M (a command's Nth frame, or its Nth to Mth, as the device takes them).
result<std::vector<fault_plan::command_range>> command_faults(const std::vector<std::string>& specs,
                                                              const char* option) {
  std::vector<fault_plan::command_range> out;
  const auto whole = [](const std::string& t) -> double {
    const auto v = text::to_double(t);
    return v && *v >= 1.0 && *v <= 1e6 && *v == std::floor(*v) ? *v : 0.0;
  };
  for (const std::string& spec : specs) {
    const auto colon = spec.find(':');
    const auto type = command_type(spec.substr(0, colon));
    double first = 0.0, last = 0.0;
    if (colon != std::string::npos) {
      const std::string n = spec.substr(colon + 1);
      const auto dash = n.find('-');
      first = whole(n.substr(0, dash));
      last = dash == std::string::npos ? first : whole(n.substr(dash + 1));
    }
    if (!type || first == 0.0 || last < first)
      return usage_error(fmt::format(
          "{}: CMD:N or CMD:N-M, CMD one of ping, configure, start, stop, home, set_delta_n, "
          "calibrate, resend and N (to M) the command's frames the device takes, counted from 1 "
          "(retries included); got {}",
          option, spec));
    out.push_back({*type, static_cast<unsigned>(first), static_cast<unsigned>(last)});
  }
  return out;
}

// AT:FOR faults (--fault-unplug, --fault-stall, --fault-tx-hold): AT device s into the run, FOR
// seconds of the named clock up to max_for_s.
result<std::vector<std::pair<double, double>>> at_for_faults(const std::vector<std::string>& specs,
                                                             const char* option, const char* clock,
                                                             double max_for_s) {
  std::vector<std::pair<double, double>> out;
  for (const std::string& u : specs) {
    const auto v = text::to_doubles(u, ':');
    if (!v || v->size() != 2 || !((*v)[0] > 0.0 && (*v)[0] <= 1e7) ||
        !((*v)[1] > 0.0 && (*v)[1] <= max_for_s))
      return usage_error(fmt::format(
          "{}: AT:FOR, AT device s into the run in (0, 1e7], FOR {} s in (0, {:g}]; got {}", option,
          clock, max_for_s, u));
    out.emplace_back((*v)[0], (*v)[1]);
  }
  return out;
}

result<fault_plan> fault_plan_of(const emulate_options& o) {
  fault_plan f;
  for (double t : o.fault_reset_at_s) {
    if (!(t > 0.0 && t <= 1e7))
      return usage_error("--fault-reset-at: device s into the run, in (0, 1e7]");
    f.reset_at_s.push_back(t);
  }
  auto unplug = at_for_faults(o.fault_unplug, "--fault-unplug", "device", 3600.0);
  if (!unplug) return unplug.err();
  f.unplug = std::move(*unplug);
  auto stall = at_for_faults(o.fault_stall, "--fault-stall", "wall", 60.0);
  if (!stall) return stall.err();
  f.stall = std::move(*stall);
  std::sort(f.stall.begin(), f.stall.end(), std::greater<>());
  auto tx_hold = at_for_faults(o.fault_tx_hold, "--fault-tx-hold", "device", 3600.0);
  if (!tx_hold) return tx_hold.err();
  f.tx_hold = std::move(*tx_hold);
  std::sort(f.tx_hold.begin(), f.tx_hold.end(), std::greater<>());
  std::sort(f.reset_at_s.begin(), f.reset_at_s.end(), std::greater<>());  // due ones at the back
  std::sort(f.unplug.begin(), f.unplug.end(), std::greater<>());
  auto lose = command_faults(o.fault_lose_reply, "--fault-lose-reply");
  if (!lose) return lose.err();
  f.lose_reply = std::move(*lose);
  auto reset = command_faults(o.fault_reset_before, "--fault-reset-before");
  if (!reset) return reset.err();
  f.reset_before = std::move(*reset);
  f.lose_boot_info = o.fault_lose_boot_info;
  return f;
}

// The commands the device takes, as the host's bytes reach it: the Nth frame of a command
// (retries counted) is where --fault-reset-before and --fault-lose-reply act.
class command_faults_on_line {
 public:
  explicit command_faults_on_line(const fault_plan& plan) : plan_(plan) {}
  // Feeds the host's bytes before the device gets them; true when the firmware is to be reset
  // before it takes them.
  bool take(const std::uint8_t* p, std::size_t n) {
    bool reset = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (!decoder_.push(p[i])) continue;
      const protocol::frame& f = decoder_.current();
      // A CONFIGURE that asks for homing (cfg_home: `record --home`, a restart after a reset)
      // is the host's homing command too: `home:N` counts it (HOME itself is not what `record`
      // sends).
      protocol::configure_msg c;
      const bool homes = f.as(c) && (c.flags & protocol::cfg_home) != 0;
      bool lose = false;
      for (const std::uint8_t as : {f.type, static_cast<std::uint8_t>(protocol::msg::home)}) {
        if (as != f.type && !homes) continue;
        const unsigned k = ++taken_[as];
        const auto named = [&](const std::vector<fault_plan::command_range>& v) {
          return std::any_of(v.begin(), v.end(), [&](const auto& r) { return r.has(as, k); });
        };
        reset = reset || named(plan_.reset_before);
        lose = lose || named(plan_.lose_reply);
      }
      if (lose) lose_.emplace_back(f.type, f.seq);
    }
    return reset;
  }
  // Whether the device's frame `f` is the reply a --fault-lose-reply names (each one once; a
  // PING's reply is its ACK and the INFO right after it).
  bool lose(const protocol::frame& f) {
    std::uint16_t of = 0;
    std::uint8_t of_type = 0;
    protocol::ack_msg a;
    protocol::nak_msg k;
    protocol::info_msg info;
    if (f.as(a)) {
      of = a.seq;
      of_type = a.of_type;
    } else if (f.as(k)) {
      of = k.seq;
      of_type = k.of_type;
    } else if (f.seq != 0 && f.as(info) && lose_info_ != 0) {
      --lose_info_;
      return true;
    } else {
      return false;
    }
    const auto it = std::find(lose_.begin(), lose_.end(), std::pair{of_type, of});
    if (it == lose_.end()) return false;
    lose_.erase(it);
    if (of_type == static_cast<std::uint8_t>(protocol::msg::ping)) ++lose_info_;
    return true;
  }

 private:
  const fault_plan& plan_;
  protocol::stream_decoder decoder_{true};
  std::map<std::uint8_t, unsigned> taken_;
  std::vector<std::pair<std::uint8_t, std::uint16_t>> lose_;  // (command type, its id)
  unsigned lose_info_ = 0;  // INFOs of PINGs whose ACK was lost, still to come
};

// Makes the frame in `wire` (its wire bytes, with the runs around it) arrive damaged beyond the
// line code's correction: two bits of one of its bytes inverted, whose nibble is not F (an
// uncorrectable byte is read as F; docs/PROTOCOL.md), so its CRC fails and the reader drops it.
// The byte count and the runs stay as they were: the frame after it arrives.
void damage_frame(std::vector<std::uint8_t>& wire) {
  std::size_t first = 0, last = wire.size();
  while (first < wire.size() && wire[first] == 0x00) ++first;
  while (last > first && wire[last - 1] == 0x00) --last;
  for (std::size_t i = first + (last - first) / 2; i < last; ++i)
    if (wire[i] != 0xFF) {
      wire[i] = static_cast<std::uint8_t>(wire[i] ^ 0x03u);
      return;
    }
}

// A symbolic link that names the line while it is there, as udev's /dev/serial/by-id names an
// adapter: a recorder given the link finds the line again after it came back under another name.
// It removes only what it made: an existing path is replaced only when it is a dangling symbolic
// link to a pseudo-terminal (left by an emulator that was killed: its pty is gone), the new link is
// made under a name of its own and renamed into place, and the link is removed only while it still
// points where this run pointed it.
class line_link {
 public:
  static result<line_link> make(std::string path) {
    struct stat st {};
    if (path.empty() || ::lstat(path.c_str(), &st) != 0) return line_link(std::move(path));
    if (!S_ISLNK(st.st_mode))
      return io_error(path, "exists and is not a symbolic link; not replaced");
    if (::stat(path.c_str(), &st) == 0)
      return io_error(path, fmt::format("is a symbolic link to {}, which exists (a line in use, or "
                                        "a link of yours); not replaced",
                                        printable(target_of(path), 200)));
    // Dangling: an earlier emulator's, whose line is gone, only when it named a pseudo-terminal
    // (a dangling link of the user's, to an unmounted disk say, is not ours to replace).
    if (!target_of(path).starts_with("/dev/pts/"))
      return io_error(path, fmt::format("is a symbolic link to {}, not a pseudo-terminal an "
                                        "earlier emulator made; not replaced",
                                        printable(target_of(path), 200)));
    return line_link(std::move(path));
  }
  line_link(line_link&& o) noexcept
      : path_(std::exchange(o.path_, {})), target_(std::exchange(o.target_, {})) {}
  line_link(const line_link&) = delete;
  line_link& operator=(const line_link&) = delete;
  line_link& operator=(line_link&&) = delete;
  ~line_link() { remove(); }
  [[nodiscard]] bool empty() const noexcept { return path_.empty(); }
  [[nodiscard]] const std::string& path() const noexcept { return path_; }
  // Points the link at `target`, replacing the old link in one step (rename). The new link is
  // made under a hidden name no other file has (symlink(2) never replaces a file).
  status point_to(const std::string& target) {
    if (path_.empty()) return ok();
    const auto slash = path_.rfind('/');
    const std::string dir = slash == std::string::npos ? "" : path_.substr(0, slash + 1);
    const std::string base = slash == std::string::npos ? path_ : path_.substr(slash + 1);
    for (unsigned k = 0; k < 100; ++k) {
      const std::string tmp = fmt::format("{}.{}.gyroflip-link.{}.{}", dir, base, ::getpid(), k);
      if (::symlink(target.c_str(), tmp.c_str()) != 0) {
        if (errno == EEXIST) continue;
        break;
      }
      if (::rename(tmp.c_str(), path_.c_str()) != 0) {
        const int e = errno;
        (void)::unlink(tmp.c_str());  // made just above
        return io_error(path_, std::string("cannot link to the line: ") + std::strerror(e));
      }
      target_ = target;
      return ok();
    }
    return io_error(path_, std::string("cannot link to the line: ") + std::strerror(errno));
  }
  // Removes the link if it is still the one this run made.
  void remove() noexcept {
    if (path_.empty() || target_.empty()) return;
    if (target_of(path_) == target_) (void)::unlink(path_.c_str());
    target_.clear();
  }

 private:
  explicit line_link(std::string p) : path_(std::move(p)) {}
  static std::string target_of(const std::string& link) {
    char buf[4096];
    const ssize_t n = ::readlink(link.c_str(), buf, sizeof buf);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
  }
  std::string path_;
  std::string target_;  // where this run pointed the link (empty: no link of ours there)
};

}  // namespace

int run_emulate(const emulate_options& o) {
  if (o.pty == !o.port.empty()) return report(usage_error("give one of --pty and --port"));
  double speed = 0.0;  // 0: as fast as the reader takes the bytes
  if (o.speed != "max") {
    const auto v = text::to_double(o.speed);
    if (!v || !(*v > 0.0 && *v <= 1e6))
      return report(usage_error("--speed: a factor in (0, 1e6] or max; got " + o.speed));
    speed = *v;
  }
  if (!(o.fault_ber >= 0.0 && o.fault_ber < 1.0) || !(o.fault_drop >= 0.0 && o.fault_drop < 1.0))
    return report(usage_error("--fault-ber and --fault-drop: probabilities in [0, 1)"));
  if (!(o.duration_s >= 0.0 && o.duration_s <= 1e7))
    return report(usage_error("--duration: 0 (until stopped) to 1e7 s"));
  auto plan = fault_plan_of(o);
  if (!plan) return report(plan.err());
  // Everything is checked before anything is opened or written: the log and the link may be
  // no input of the run (a preset, a temperature profile, the port) and no one file.
  if (auto s = io::check_outputs(std::array{o.sensor, o.temp_profile, o.port},
                                 std::array{o.log, o.link, o.truth});
      !s)
    return report(s.err());
  if (auto s = sent_log::check(o.log); !s) return report(s.err());
  auto link = line_link::make(o.link);
  if (!link) return report(link.err());
  auto cfg = emulator_config_of(o);
  if (!cfg) return report(cfg.err());
  auto made = host::emulator::make(*cfg);
  if (!made) return report(made.err());
  host::emulator& emu = **made;
  if (auto s = write_truth(o.truth, emu); !s) return report(s.err());
  const auto open_line = [&]() -> result<host::serial_line> {
    auto l = o.pty ? host::serial_line::open_pty() : host::serial_line::open_device(o.port);
    if (!l) return l;
    if (auto s = link->point_to(l->peer_path()); !s) return s.err();
    // The one line a script parses (again after the line came back).
    fmt::print("gyroflip emulate: the rig is on {}\n",
               link->empty() ? l->peer_path() : link->path());
    std::fflush(stdout);
    return l;
  };
  std::optional<host::serial_line> line;
  if (auto l = open_line(); !l)
    return report(l.err());
  else
    line.emplace(std::move(*l));
  // Last: opening the log truncates it.
  auto log = sent_log::open(o.log);
  if (!log) return report(log.err());
  const std::atomic<bool>& stop_requested = catch_stop_signals({SIGINT, SIGTERM});
  std::signal(SIGPIPE, SIG_IGN);

  using steady = std::chrono::steady_clock;
  host::link_faults faults(o.fault_ber, o.fault_drop, o.seed ^ 0x5EEDF00DULL);
  // The clean stream, every frame (a frame sent again for RESEND too), logged the first time its
  // number goes out: a DWELL that did not fit the transmit ring goes out first from the history.
  protocol::stream_decoder monitor{true};
  // Per boot that made the frames (a frame of the last boot may still go out after a reset): a
  // number of the old boot's does not hide the new boot's frame of that number.
  std::map<unsigned, first_sight> logged;
  std::vector<std::uint8_t> to_device, out, frame_wire;
  std::uint64_t frames_named = 0;  // frames lost by --fault-lose-reply or --fault-lose-boot-info
  std::uint8_t buf[4096];
  constexpr std::uint32_t chunk_ticks = host::emulator::tick_hz / 100;  // 10 ms of device time
  const auto wall_start = steady::now();
  double back_at_s = 0.0;     // while the line is gone: the device time it comes back
  double stall_s = 0.0;       // a --fault-stall due: its wall seconds (0: none)
  double tx_free_at_s = 0.0;  // a --fault-tx-hold ends at this device time (0: none held)
  std::uint64_t frames_unplugged = 0;
  bool frame_unplugged = false;  // a byte of the frame being sent went out while the line was gone
  bool reader_gone = false;      // at max speed: the reader has left more than 256 bytes for 2 s
  std::optional<double> run_start_s;  // device time of the first run: faults count from it
  // On a faulty line, max speed is at most max_faulty_speed times the rig's: a RESEND must come
  // back while the device still holds the frame (its history, ~6 s of the rig's time). A host
  // answers within milliseconds; at 25x that is a fraction of a second of the rig's time, as a
  // host's tens of ms are on a real line, and a test machine loaded several times over (a
  // recorder descheduled for 200 ms) leaves margin. Flat out, a host's few ms would be seconds.
  const bool faulty = o.fault_ber > 0.0 || o.fault_drop > 0.0 || !plan->unplug.empty();
  pace pacer(speed > 0.0 ? speed : faulty ? max_faulty_speed : 0.0);
  // The host's bytes to the device (waiting up to `wait_ms` for them).
  command_faults_on_line commands(*plan);
  // A boot's INFO is still to come (and to be lost): the first boot's, then each reset's.
  bool lose_next_boot_info = plan->lose_boot_info;
  const auto reset = [&] {
    emu.reset();
    monitor.frames().reset_sequence();  // the rebooted device numbers its frames from 0
    if (logged.size() > 2) logged.erase(logged.begin());
    lose_next_boot_info = plan->lose_boot_info;
  };
  const auto exchange = [&](int wait_ms) -> status {
    if (line && to_device.empty()) {
      auto r = line->read(buf, sizeof buf, wait_ms);
      if (!r) return r.err();
      to_device.assign(buf, buf + *r);
      // A command the firmware is to meet rebooted: the reset comes before it takes the bytes.
      if (commands.take(to_device.data(), to_device.size())) reset();
    } else if (wait_ms > 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
    }
    // What the device's queue does not take now waits (a read of more than its 1 KB must not
    // block the host's bytes forever).
    if (!to_device.empty())
      to_device.erase(to_device.begin(),
                      to_device.begin() + static_cast<std::ptrdiff_t>(
                                              emu.send(to_device.data(), to_device.size())));
    return ok();
  };
  emu.boot();
  while (!stop_requested && (o.duration_s == 0.0 || emu.time_s() < o.duration_s)) {
    if (!run_start_s && emu.device().state() == protocol::device_state::running)
      run_start_s = emu.time_s();
    const double run_s = run_start_s ? emu.time_s() - *run_start_s : -1.0;
    if (!plan->reset_at_s.empty() && run_s >= plan->reset_at_s.back()) {
      plan->reset_at_s.pop_back();
      reset();
    }
    if (stall_s == 0.0 && !plan->stall.empty() && run_s >= plan->stall.back().first) {
      stall_s = plan->stall.back().second;
      plan->stall.pop_back();
    }
    if (!plan->tx_hold.empty() && run_s >= plan->tx_hold.back().first) {
      tx_free_at_s = std::max(tx_free_at_s, emu.time_s() + plan->tx_hold.back().second);
      plan->tx_hold.pop_back();
      emu.hold_transmitter(true);
    }
    if (tx_free_at_s > 0.0 && emu.time_s() >= tx_free_at_s) {
      tx_free_at_s = 0.0;
      emu.hold_transmitter(false);
    }
    if (line && !plan->unplug.empty() && run_s >= plan->unplug.back().first) {
      back_at_s = emu.time_s() + plan->unplug.back().second;
      plan->unplug.pop_back();
      // The cable goes between frames: what is already on the wire reaches the reader (so the
      // frames lost are exactly those sent while the line is gone), then its reads fail, as
      // with a vanished adapter.
      (void)line->drain(500);
      line.reset();
      link->remove();
      to_device.clear();
    }
    if (!line && emu.time_s() >= back_at_s) {
      auto l = open_line();
      if (!l) return report(l.err());
      line.emplace(std::move(*l));
    }
    emu.run(chunk_ticks);
    // Device to host: the log sees the clean stream, the line the faulty one (or nothing). The
    // bytes of a frame wait in `frame_wire` until it is whole: a frame a fault names (a reply,
    // a boot's INFO) goes out damaged.
    out.clear();
    for (std::size_t n; (n = emu.receive(buf, sizeof buf)) > 0;)
      for (std::size_t i = 0; i < n; ++i) {
        std::uint8_t b = 0;
        // What the device sends while the line is gone is lost (the faults' draws go on).
        if (faults.pass(buf[i], b) && line) frame_wire.push_back(b);
        // A frame is lost if any of its bytes went out while the line was gone: one that
        // straddles the replug arrives without its head.
        frame_unplugged = frame_unplugged || !line;
        if (!monitor.push(buf[i])) continue;
        const protocol::frame& fr = monitor.current();
        bool named = commands.lose(fr);
        if (lose_next_boot_info && fr.type == static_cast<std::uint8_t>(protocol::msg::info) &&
            fr.seq == 0) {
          named = true;
          lose_next_boot_info = false;
        }
        if (named) {
          damage_frame(frame_wire);
          ++frames_named;
        }
        out.insert(out.end(), frame_wire.begin(), frame_wire.end());
        frame_wire.clear();
        const bool lost = named || frame_unplugged || faults.last_frame_hit();
        if (frame_unplugged) ++frames_unplugged;
        frame_unplugged = false;
        // The boot that made it: a DWELL's by when it ended, any other frame's the boot now.
        protocol::dwell_msg dwell;
        const unsigned maker =
            monitor.current().as(dwell) ? emu.boot_at(dwell.t_end_ticks) : emu.boots();
        if (!logged[maker].take(monitor.current().seq)) continue;
        if (auto s = log->add(monitor.current(), emu.time_s(), lost, emu, maker); !s)
          return report(s.err());
      }
    // A reader that does not keep up holds the device's time (the stream stays whole).
    for (std::size_t done = 0; line && done < out.size() && !stop_requested;) {
      auto w = line->write(out.data() + done, out.size() - done, 100);
      if (!w) return report(w.err());
      done += *w;
    }
    // A stall due: right after the next frame went out (a peer stopped just after it spoke).
    if (stall_s > 0.0 && line && !out.empty()) {
      const auto until = steady::now() + std::chrono::duration<double>(stall_s);
      stall_s = 0.0;
      while (!stop_requested && steady::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    // Pace: wait for the host's bytes until the wall clock has caught up with the device's time
    // (pacer). At max speed, the reader's pace besides: the device's time waits while more than
    // 256 bytes are unread, as a real line never holds seconds of the rig's output between the
    // rig and its reader. It used to run on at 10 ms of its time per ms of wall time: a recorder
    // held up for a second (an fdatasync on a loaded CI machine) found the frames it then asked
    // for again gone from the device's history, and the first cycle's dwells were counted lost
    // (CI, Faults/LinkFigures.DwellsRecordedOfDwellsSent/drop_1e2: 134 of 136). A reader that
    // has not read for 2 s is taken for none (an emulator nobody listens to still runs its
    // --duration): the device runs on at that pace until the reader takes the bytes again.
    int wait_ms = pacer.wait_ms(emu.time_s(), steady::now());
    const bool behind = speed == 0.0 && line && line->unread() > 256;
    if (behind) wait_ms = std::max(wait_ms, 1);
    if (auto s = exchange(wait_ms); !s) return report(s.err());
    if (!behind) {
      reader_gone = false;
    } else if (!reader_gone) {
      const auto until = steady::now() + std::chrono::seconds(2);
      while (!stop_requested && line && line->unread() > 256 && steady::now() < until)
        if (auto s = exchange(1); !s) return report(s.err());
      reader_gone = line && line->unread() > 256;
    }
  }
  // The last frames reach a reader before the line closes (closing a pty discards what the
  // reader has not yet read).
  if (line && !stop_requested) (void)line->drain(1000);
  const double wall_s = std::chrono::duration<double>(steady::now() - wall_start).count();
  const host::link_fault_counts& k = faults.counts();
  fmt::print(stderr,
             "gyroflip emulate: board serial {}; {:.1f} s simulated in {:.1f} s; {} frames sent, "
             "{} hit by faults ({} bits flipped, {} bytes dropped), {} while the line was gone, {} "
             "lost as the fault options named\n",
             emu.config().serial, emu.time_s(), wall_s, k.frames, k.frames_hit, k.bits_flipped,
             k.bytes_dropped, frames_unplugged, frames_named);
  return 0;
}

}  // namespace gyroflip::app
