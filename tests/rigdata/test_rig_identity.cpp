// Whose dwells a rig recording holds (issue 32 item 3, the reader's side): a recorder before
// issue 32 stored frames of a reconnected line before the INFO that named the board, and a
// STATUS of another boot with no reset recorded went unseen; 97 dwells of a second board were
// used by export and calibrate. The reader uses nothing that arrived before the device was
// identified, nothing after an INFO of another serial, nothing of a boot no reset announced
// (until its INFO), and says so. The files are written byte by byte as such a recorder wrote
// them (format 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/messages.hpp"
#include "gyroflip/rigdata/rig_run.hpp"
#include "support/synthetic_gfr.hpp"

namespace {

namespace gfr = gyroflip::rigdata::gfr;
namespace p = gyroflip::protocol;
using bytes = std::vector<std::uint8_t>;

// A file of format 4, record by record, at host times the test sets.
class legacy_file {
 public:
  legacy_file() : b_(gyroflip::test::encode_file_header(4)) {
    const std::string m =
        R"({"scale_factor_v_per_dps":0.0125,"temp_v_per_c":0.0084,"temp_at_0v_c":24.85})";
    put(gfr::kind::meta, bytes(m.begin(), m.end()));
  }
  void at(double s) { host_us_ = static_cast<std::uint64_t>(s * 1e6); }
  void info(std::uint32_t serial, std::uint16_t boot) {
    p::info_msg m;
    m.protocol = p::protocol_version;
    m.serial = serial;
    m.tick_hz = 1000;
    m.range = 4;
    m.boot_count = boot;
    put(gfr::kind::info, gyroflip::test::payload_of(m));
  }
  void configure() { put(gfr::kind::configure, gyroflip::test::payload_of(p::configure_msg{})); }
  // The ACK of START (frame `seq`) and the START record naming it.
  void start(std::uint16_t seq) {
    p::ack_msg a;
    a.of_type = static_cast<std::uint8_t>(p::msg::start);
    a.at_seq = seq;
    frame(p::msg::ack, seq, gyroflip::test::payload_of(a));
    const auto crc = p::configure_crc(p::configure_msg{});
    put(gfr::kind::start,
        bytes{static_cast<std::uint8_t>(seq), static_cast<std::uint8_t>(seq >> 8),
              static_cast<std::uint8_t>(crc), static_cast<std::uint8_t>(crc >> 8)});
  }
  // Dwell `k` of a run (cycle k/2, position k%2) at device time t_ms (1 kHz ticks), its mean
  // code telling which board sent it.
  void dwell(std::uint16_t seq, std::uint32_t k, std::uint32_t t_ms, std::int64_t code) {
    p::dwell_msg d;
    d.cycle = k / 2;
    d.position = static_cast<std::uint8_t>(k % 2);
    d.t_start_ticks = t_ms;
    d.t_end_ticks = t_ms + 500;
    d.n = 256;
    d.code_sum = 256 * code;
    frame(p::msg::dwell, seq, gyroflip::test::payload_of(d));
  }
  void status(std::uint16_t seq, std::uint16_t boot, std::uint32_t uptime_ms) {
    p::status_msg s;
    s.state = static_cast<std::uint8_t>(p::device_state::running);
    s.uptime_ticks = uptime_ms;
    s.boot_count = boot;
    frame(p::msg::status, seq, gyroflip::test::payload_of(s));
  }
  void gap(gfr::gap_reason r, std::uint32_t count) {
    put(gfr::kind::gap,
        bytes{static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(count),
              static_cast<std::uint8_t>(count >> 8), static_cast<std::uint8_t>(count >> 16),
              static_cast<std::uint8_t>(count >> 24)});
  }
  void stop(gfr::stop_reason r) { put(gfr::kind::stop, bytes{static_cast<std::uint8_t>(r)}); }

  [[nodiscard]] gyroflip::rigdata::rig_run read() const {
    auto f = gfr::parse(b_, "x.gfr");
    EXPECT_TRUE(f) << f.err().message;
    auto run = gyroflip::rigdata::interpret(*f, "x.gfr", false);
    EXPECT_TRUE(run) << run.err().message;
    return run ? *run : gyroflip::rigdata::rig_run{};
  }

 private:
  void frame(p::msg type, std::uint16_t seq, const bytes& pl) {
    bytes b = pl;
    const std::uint8_t head[3] = {static_cast<std::uint8_t>(type), static_cast<std::uint8_t>(seq),
                                  static_cast<std::uint8_t>(seq >> 8)};
    b.insert(b.begin(), head, head + 3);
    put(gfr::kind::frame, b);
  }
  void put(gfr::kind k, const bytes& body) {
    const bytes r = gyroflip::test::encode_record(k, host_us_, body);
    b_.insert(b_.end(), r.begin(), r.end());
  }
  bytes b_;
  std::uint64_t host_us_ = 0;
};

// Dwells `first`.. `first + n - 1` of a run, one a second from host time `host_s` and device
// time `device_ms` (ms), each followed by a STATUS of `boot`; `seq` is the next frame number.
void dwells(legacy_file& f, std::uint16_t& seq, std::uint16_t boot, std::uint32_t first,
            std::uint32_t n, double host_s, std::uint32_t device_ms, std::int64_t code) {
  for (std::uint32_t k = first; k < first + n; ++k) {
    f.at(host_s + (k - first));
    f.dwell(seq++, k, device_ms + 1000 * (k - first), code);
    f.status(seq++, boot, device_ms + 600 + 1000 * (k - first));
  }
}

// Board A (serial 7, code 1000): 20 dwells of one run, a STATUS a second.
void board_a(legacy_file& f) {
  f.info(7, 1);
  f.configure();
  f.start(2);
  std::uint16_t seq = 3;
  dwells(f, seq, 1, 0, 20, 1.0, 1000, 1000);
}

std::size_t dwells_with_code(const gyroflip::rigdata::rig_run& run, std::int64_t code) {
  std::size_t n = 0;
  for (const auto& d : run.dwells) n += d.d.code_sum == 256 * code ? 1 : 0;
  return n;
}

bool warned(const gyroflip::rigdata::rig_run& run, const std::string& what) {
  for (const auto& w : run.warnings)
    if (w.find(what) != std::string::npos) return true;
  return false;
}

// The review's case: the port lost at 20.5 s, another board (B, code 3000) on the line when it
// came back; the recorder stored B's frames while its PING waited for INFO, then wrote the link
// GAP and, on B's INFO (serial 8), STOP (another device). B's 6 dwells were used.
TEST(RigIdentity, WhatArrivedBeforeAReconnectedBoardWasIdentifiedIsNotUsed) {
  legacy_file f;
  board_a(f);
  std::uint16_t seq = 500;
  for (std::uint32_t k = 0; k < 6; ++k) {
    f.at(23.0 + 0.05 * k);
    f.dwell(seq++, 40 + k, 90000 + 1000 * k, 3000);
    f.status(seq++, 1, 90500 + 1000 * k);  // the same boot count as A's
  }
  f.at(23.6);
  f.gap(gfr::gap_reason::link_lost, 3100);  // the port was lost 3.1 s before: at 20.5 s
  f.stop(gfr::stop_reason::device_changed);
  const auto run = f.read();
  EXPECT_EQ(dwells_with_code(run, 1000), 20u);
  EXPECT_EQ(dwells_with_code(run, 3000), 0u);
  EXPECT_EQ(run.unidentified, 6u);
  EXPECT_TRUE(warned(run, "6 dwells came from a device that was not identified"))
      << run.warnings[0];
}

// A recorder that stores the INFO of whatever answers after a reconnect: an INFO of another
// serial starts another board's data, which is never merged into this board's.
TEST(RigIdentity, AnotherSerialsDwellsAreKeptApart) {
  legacy_file f;
  board_a(f);
  f.at(24.0);
  f.gap(gfr::gap_reason::link_lost, 3000);
  f.info(8, 1);
  f.configure();
  f.start(2);
  for (std::uint32_t k = 0; k < 6; ++k) {
    f.at(25.0 + k);
    f.dwell(static_cast<std::uint16_t>(3 + k), k, 5000 + 1000 * k, 3000);
  }
  const auto run = f.read();
  EXPECT_EQ(dwells_with_code(run, 1000), 20u);
  EXPECT_EQ(dwells_with_code(run, 3000), 0u);
  EXPECT_EQ(run.other_board, 6u);
  EXPECT_EQ(run.info.serial, 7u);
  EXPECT_TRUE(warned(run, "another board (serial 8; this file's board is 7)"));
}

// A STATUS of another boot where no reset was recorded (another board that answered for this
// one, or a reset the recorder did not see and so did not home after): what follows the last
// STATUS of the identified boot is not labelled, until the boot is set up again.
TEST(RigIdentity, AStatusOfAnotherBootWithNoResetRecordedEndsWhatIsUsed) {
  for (const bool same_count : {false, true}) {
    SCOPED_TRACE(same_count ? "uptime went back, same boot count" : "another boot count");
    legacy_file f;
    board_a(f);
    std::uint16_t seq = 43;
    for (std::uint32_t k = 20; k < 30; ++k) {
      f.at(1.0 + k);
      f.dwell(seq++, k, 1000 + 1000 * k, 3000);
      f.status(seq++, same_count ? 1 : 2, 200 + 1000 * (k - 20));
    }
    const auto run = f.read();
    EXPECT_EQ(dwells_with_code(run, 1000), 20u);
    EXPECT_EQ(dwells_with_code(run, 3000), 0u);
    EXPECT_EQ(run.unidentified + run.unknown_boot, 10u);
  }
}

// The control: a reset the recorder saw (GAP, the new boot's INFO, homing, START) is a new run
// of the same board, used whole; so is a reconnect to the same board, but for what arrived
// before it was known again.
TEST(RigIdentity, AResetAndAReconnectOfTheSameBoardAreUsed) {
  legacy_file f;
  board_a(f);
  f.at(21.0);
  f.gap(gfr::gap_reason::device_reset, 0);
  f.status(1, 2, 300);
  f.info(7, 2);
  f.configure();
  f.start(4);
  std::uint16_t seq = 5;
  dwells(f, seq, 2, 0, 10, 23.0, 2000, 2000);
  // The port lost at 33.5 s; back at 36.5 s: one dwell stored while the PING waited.
  f.at(36.4);
  f.dwell(seq++, 10, 15000, 2000);
  f.at(36.5);
  f.gap(gfr::gap_reason::link_lost, 3000);
  dwells(f, seq, 2, 11, 4, 48.0, 13000, 2000);
  f.stop(gfr::stop_reason::duration);
  const auto run = f.read();
  EXPECT_EQ(dwells_with_code(run, 1000), 20u);
  EXPECT_EQ(dwells_with_code(run, 2000), 14u);
  EXPECT_EQ(run.unidentified, 1u);
  EXPECT_EQ(run.lost_dwells, 1u);
  EXPECT_EQ(run.device_resets, 1u);
  EXPECT_EQ(run.unknown_boot, 0u);
}

}  // namespace
