/// \file
/// \brief `gyroflip emulate` (docs/EMULATOR.md): the firmware core and the simulated rig behind
/// a pseudo-terminal or a serial device, paced to real time or run as fast as the reader takes.
#include "cmd_emulate.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <thread>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "commands.hpp"
#include "firmware/protocol/frame.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "host/emulator/emulator.hpp"
#include "host/emulator/link_faults.hpp"
#include "host/serial/serial_line.hpp"
#include "physics_options.hpp"
#include "stop_signal.hpp"

namespace gyroflip::app {

namespace {

// Writes one CSV row per DWELL the device sent (before link faults): the ground truth of a run.
class sent_log {
 public:
  static result<sent_log> open(const std::string& path) {
    if (path.empty()) return sent_log(nullptr, path);
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (f == nullptr) return io_error(path, "cannot create");
    std::fputs(
        "seq,cycle,position,t_start_ticks,t_end_ticks,n,code_sum,code_min,code_max,n_temp,"
        "temp_sum,ax_high_ticks,ax_period_ticks,ay_high_ticks,ay_period_ticks,flags,sent_time_s,"
        "hit\n",
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
  status add(const protocol::frame& fr, double time_s, bool hit) {
    protocol::dwell_msg d;
    if (f_ == nullptr || !fr.as(d)) return ok();
    fmt::print(f_, "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.6f},{}\n", fr.seq, d.cycle,
               d.position, d.t_start_ticks, d.t_end_ticks, d.n, d.code_sum, d.code_min, d.code_max,
               d.n_temp, d.temp_sum, d.ax_high_ticks, d.ax_period_ticks, d.ay_high_ticks,
               d.ay_period_ticks, d.flags, time_s, hit ? 1 : 0);
    if (std::fflush(f_) != 0 || std::ferror(f_)) return io_error(path_, "write failed");
    return ok();
  }

 private:
  sent_log(std::FILE* f, std::string path) : f_(f), path_(std::move(path)) {}
  std::FILE* f_;
  std::string path_;
};

result<host::emulator_config> emulator_config_of(const emulate_options& o) {
  host::emulator_config c;
  auto preset = load_physics(o.sensor, o.temp_c, o.temp_profile, o.rate_profile, c.sim);
  if (!preset) return preset.err();
  c.sim.lat_deg = o.lat_deg;
  c.sim.axis = o.axis;
  c.sim.table_axis = o.table_axis;
  c.sim.adc.filter_word = o.filter_word;
  c.sim.adc.chop = !o.no_chop;
  c.sim.stepper.steps_per_rev = o.steps_per_rev;
  c.sim.power_on_before_s = o.power_on_before_s;
  c.sim.seed = o.seed;
  return c;
}

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
  auto cfg = emulator_config_of(o);
  if (!cfg) return report(cfg.err());
  auto made = host::emulator::make(*cfg);
  if (!made) return report(made.err());
  host::emulator& emu = **made;
  auto log = sent_log::open(o.log);
  if (!log) return report(log.err());
  auto line = o.pty ? host::serial_line::open_pty() : host::serial_line::open_device(o.port);
  if (!line) return report(line.err());
  const std::atomic<bool>& stop_requested = catch_stop_signals({SIGINT, SIGTERM});
  std::signal(SIGPIPE, SIG_IGN);
  // The one line a script parses; then the run.
  fmt::print("gyroflip emulate: the rig is on {}\n", line->peer_path());
  std::fflush(stdout);

  host::link_faults faults(o.fault_ber, o.fault_drop, o.seed ^ 0x5EEDF00DULL);
  protocol::frame_decoder monitor;
  std::vector<std::uint8_t> to_device, out;
  std::uint8_t buf[4096];
  constexpr std::uint32_t chunk_ticks = host::emulator::tick_hz / 100;  // 10 ms of device time
  const auto wall_start = std::chrono::steady_clock::now();
  emu.boot();
  while (!stop_requested && (o.duration_s == 0.0 || emu.time_s() < o.duration_s)) {
    emu.run(chunk_ticks);
    // Device to host: the log sees the clean stream, the line the faulty one.
    out.clear();
    for (std::size_t n; (n = emu.receive(buf, sizeof buf)) > 0;)
      for (std::size_t i = 0; i < n; ++i) {
        std::uint8_t b = 0;
        if (faults.pass(buf[i], b)) out.push_back(b);
        if (monitor.push(buf[i]))
          if (auto s = log->add(monitor.current(), emu.time_s(), faults.last_frame_hit()); !s)
            return report(s.err());
      }
    // A reader that does not keep up holds the device's time (the stream stays whole).
    for (std::size_t done = 0; done < out.size() && !stop_requested;) {
      auto w = line->write(out.data() + done, out.size() - done, 100);
      if (!w) return report(w.err());
      done += *w;
    }
    // Pace to real time: wait for the host's bytes until the wall clock catches up.
    int wait_ms = 0;
    if (speed > 0.0) {
      const double due_s = emu.time_s() / speed;
      const double now_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      wait_ms = due_s > now_s ? static_cast<int>(std::ceil((due_s - now_s) * 1e3)) : 0;
    }
    if (to_device.empty()) {
      auto r = line->read(buf, sizeof buf, wait_ms);
      if (!r) return report(r.err());
      to_device.assign(buf, buf + *r);
    } else if (wait_ms > 0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
    }
    if (!to_device.empty() && emu.send(to_device.data(), to_device.size())) to_device.clear();
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  const host::link_fault_counts& k = faults.counts();
  std::fprintf(stderr,
               "gyroflip emulate: %.1f s simulated in %.1f s; %llu frames sent, %llu hit by faults "
               "(%llu bits flipped, %llu bytes dropped)\n",
               emu.time_s(), wall_s, static_cast<unsigned long long>(k.frames),
               static_cast<unsigned long long>(k.frames_hit),
               static_cast<unsigned long long>(k.bits_flipped),
               static_cast<unsigned long long>(k.bytes_dropped));
  return 0;
}

}  // namespace gyroflip::app
