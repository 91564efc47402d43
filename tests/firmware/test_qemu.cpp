// The Cortex-M3 image under QEMU (issue 8): boot it, exchange PING/INFO/CONFIGURE/START with it
// over its UART through the protocol decoder, and check 20+ DWELLs against the in-image model.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "firmware/ports/cortex-m3-qemu/model_codes.hpp"
#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"

extern char** environ;

namespace {

using namespace gyroflip;
using clock_type = std::chrono::steady_clock;

struct qemu_process {
  pid_t pid = -1;
  int to = -1;    // its UART's input
  int from = -1;  // its UART's output

  explicit qemu_process(const std::string& elf) {
    int in[2];
    int out[2];
    if (pipe(in) != 0 || pipe(out) != 0) return;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, in[0], 0);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    // QEMU's own messages ("terminating on signal 15") are not the test's output.
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    for (const int fd : {in[0], in[1], out[0], out[1]}) posix_spawn_file_actions_addclose(&fa, fd);
    std::vector<std::string> args = {"qemu-system-arm", "-M", "mps2-an385",
                                     // Virtual time from executed instructions only (16 ns
                                     // each; sleep=off: no idle time taken from the host's
                                     // clock): a host that stalls QEMU (a loaded CI machine)
                                     // cannot make the firmware's timer jump and its RDY wait
                                     // time out. shift=auto let it (fresh Debian 12, load).
                                     "-icount", "shift=4,sleep=off", "-display", "none", "-monitor",
                                     "none", "-serial", "stdio", "-semihosting-config",
                                     "enable=on,target=native", "-kernel", elf};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    if (posix_spawnp(&pid, "qemu-system-arm", &fa, nullptr, argv.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&fa);
    close(in[0]);
    close(out[1]);
    to = in[1];
    from = out[0];
  }
  ~qemu_process() {
    if (to >= 0) close(to);
    if (from >= 0) close(from);
    if (pid > 0) {
      kill(pid, SIGTERM);
      int st = 0;
      waitpid(pid, &st, 0);
    }
  }
  qemu_process(const qemu_process&) = delete;
  qemu_process& operator=(const qemu_process&) = delete;
};

struct host_side {
  explicit host_side(qemu_process& proc) : q(proc) {}
  qemu_process& q;
  protocol::stream_decoder dec;
  uint16_t seq = 0;
  struct got {
    uint8_t type;
    uint16_t seq;
    std::vector<uint8_t> payload;
  };
  std::vector<got> frames;

  template <class M>
  uint16_t send(const M& m) {
    uint8_t buf[protocol::max_wire_bytes];
    const uint16_t s = seq++;
    const size_t n = protocol::encode_wire(m, s, buf, sizeof buf, true);
    EXPECT_EQ(write(q.to, buf, n), static_cast<ssize_t>(n));
    return s;
  }
  /// Reads until `pred()` or `seconds` pass; true when pred held.
  template <class P>
  bool read_until(P pred, double seconds) {
    const auto end = clock_type::now() + std::chrono::duration<double>(seconds);
    uint8_t buf[512];
    while (!pred()) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(end - clock_type::now());
      if (left.count() <= 0) return false;
      pollfd p{q.from, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
      const ssize_t n = read(q.from, buf, sizeof buf);
      if (n <= 0) return false;  // QEMU exited
      for (ssize_t i = 0; i < n; ++i)
        if (dec.push(buf[i])) {
          const auto& f = dec.current();
          frames.push_back({f.type, f.seq, {f.payload, f.payload + f.length}});
        }
    }
    return true;
  }
  template <class M>
  std::vector<M> all() const {
    std::vector<M> out;
    for (const auto& g : frames) {
      protocol::frame f;
      f.type = g.type;
      f.seq = g.seq;
      f.payload = g.payload.data();
      f.length = g.payload.size();
      M m;
      if (f.as(m)) out.push_back(m);
    }
    return out;
  }
  template <class M>
  size_t count() const {
    return all<M>().size();
  }
  bool acked(uint16_t s) const {
    for (const auto& a : all<protocol::ack_msg>())
      if (a.seq == s) return true;
    return false;
  }
};

TEST(Qemu, TheCortexM3ImageSpeaksTheProtocolAndItsDwellsMatchTheModel) {
  const std::string elf = GYROFLIP_CM3_ELF;
  ASSERT_TRUE(std::filesystem::exists(elf)) << elf;
  qemu_process q(elf);
  ASSERT_GT(q.pid, 0) << "qemu-system-arm did not start (scripts/setup installs it)";
  host_side h(q);
  // INFO at boot.
  ASSERT_TRUE(h.read_until([&] { return h.count<protocol::info_msg>() >= 1; }, 20));
  const uint16_t ping = h.send(protocol::ping_msg{});
  ASSERT_TRUE(
      h.read_until([&] { return h.acked(ping) && h.count<protocol::info_msg>() >= 2; }, 20));
  const auto info = h.all<protocol::info_msg>().back();
  EXPECT_EQ(info.protocol, protocol::protocol_version);
  EXPECT_EQ(info.tick_hz, 1000000u);
  EXPECT_EQ(info.serial, 0x51AB0001u);

  protocol::configure_msg c;  // the default positions (the model's B is 100 steps), quick dwells
  c.n_avg = 16;
  c.n_temp = 1;
  c.settle_ms = 5;
  c.step_rate_sps = 2000;
  c.start_rate_sps = 1000;
  c.ramp_sps2 = 50000;
  const uint16_t cs = h.send(c);
  ASSERT_TRUE(h.read_until([&] { return h.acked(cs); }, 20)) << "CONFIGURE not acknowledged";
  protocol::start_msg start;
  start.config_crc = protocol::configure_crc(c);
  const uint16_t ss = h.send(start);
  ASSERT_TRUE(h.read_until([&] { return h.acked(ss); }, 20));
  ASSERT_TRUE(h.read_until([&] { return h.count<protocol::dwell_msg>() >= 20; }, 90))
      << h.count<protocol::dwell_msg>() << " DWELLs";
  const auto dwells = h.all<protocol::dwell_msg>();
  uint32_t index = 0;
  for (size_t i = 0; i < 20; ++i) {
    const auto& d = dwells[i];
    SCOPED_TRACE(i);
    EXPECT_EQ(d.cycle, i / 2);
    EXPECT_EQ(d.position, i % 2);
    EXPECT_EQ(d.flags, 0);
    ASSERT_EQ(d.n, 16);
    int64_t sum = 0;
    for (uint32_t k = 0; k < 16; ++k) sum += fw::qemu::model_gyro_code(index + k, d.position == 1);
    EXPECT_EQ(d.code_sum, sum);
    EXPECT_EQ(d.n_temp, 1);
    EXPECT_EQ(d.temp_sum, fw::qemu::model_temp);
    // 16 conversions of 2 ms (1 MHz ticks): at least 32 ms.
    EXPECT_GE(d.t_end_ticks - d.t_start_ticks, 16u * 1999u);
    EXPECT_GT(d.ax_period_ticks, 0u);  // the PWM tilt inputs were captured
    index += 16;
  }
  const uint16_t st = h.send(protocol::stop_msg{});
  ASSERT_TRUE(h.read_until([&] { return h.acked(st); }, 20));
  EXPECT_EQ(h.dec.counts().bad(), 0u);
  EXPECT_EQ(h.dec.counts().missing, 0u);
  EXPECT_EQ(h.dec.line().corrected + h.dec.line().uncorrectable, 0u);
}

}  // namespace
