// `gyroflip emulate` through a real pseudo-terminal (issue 9): what a reader decodes is what the
// device sent (its --log), and link faults lose exactly the frames they hit.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace p = gyroflip::protocol;

struct log_row {
  std::vector<long long> v;  // the columns from cycle up to flags
  bool hit = false;
};

// seq -> row of the emulator's --log (seq numbers do not wrap in these short runs).
std::map<unsigned, log_row> read_log(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  std::map<unsigned, log_row> rows;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string cell;
    log_row r;
    std::vector<std::string> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    EXPECT_EQ(cells.size(), 19u) << line;
    for (size_t i = 1; i < 16; ++i) r.v.push_back(std::stoll(cells[i]));
    r.hit = cells[17] == "1";
    // Where the table truly stood during the dwell: the position the DWELL names.
    EXPECT_EQ(std::stod(cells[18]), r.v[1] == 0 ? 0.0 : 180.0) << line;
    rows[static_cast<unsigned>(std::stoul(cells[0]))] = r;
  }
  return rows;
}

std::vector<long long> fields(const p::dwell_msg& d) {
  return {d.cycle,         d.position,        d.t_start_ticks, d.t_end_ticks,     d.n,
          d.code_sum,      d.code_min,        d.code_max,      d.n_temp,          d.temp_sum,
          d.ax_high_ticks, d.ax_period_ticks, d.ay_high_ticks, d.ay_period_ticks, d.flags};
}

struct run_result {
  std::map<unsigned, p::dwell_msg> dwells;  // by seq
  p::decoder_counts counts;
  std::string summary;
};

// Starts the emulator on a pty, configures and starts the device, reads until the emulator has
// run `seconds` of simulated time and gone quiet.
run_result emulate(const std::string& extra, const std::string& log, double seconds) {
  run_result out;
  const std::string cmd = std::string(GYROFLIP_EXE) + " emulate --pty --speed max --seed 5" +
                          " --duration " + std::to_string(seconds) + " --log " + log + " " + extra +
                          " 2>" + log + ".err";
  std::FILE* emu = popen(cmd.c_str(), "r");
  EXPECT_NE(emu, nullptr);
  if (emu == nullptr) return out;
  char first[256] = {};
  EXPECT_NE(std::fgets(first, sizeof first, emu), nullptr);
  std::string path(first);
  path = path.substr(path.find("/dev/"));
  path = path.substr(0, path.find_first_of(" \n"));
  const int fd = open(path.c_str(), O_RDWR | O_NOCTTY);
  EXPECT_GE(fd, 0) << path;
  termios t{};
  tcgetattr(fd, &t);
  cfmakeraw(&t);
  tcsetattr(fd, TCSANOW, &t);
  uint16_t seq = 0;
  const auto send = [&](const auto& m) {
    uint8_t buf[p::max_wire_bytes];
    const size_t n = p::encode_wire(m, seq++, buf, sizeof buf, true);
    EXPECT_EQ(write(fd, buf, n), static_cast<ssize_t>(n));
  };
  send(p::configure_msg{});
  p::start_msg start;
  start.config_crc = p::configure_crc(p::configure_msg{});
  send(start);
  p::stream_decoder dec;
  uint8_t in[4096];
  for (;;) {
    pollfd pf{fd, POLLIN, 0};
    if (poll(&pf, 1, 1500) <= 0) break;  // quiet: the emulator has finished
    const ssize_t got = read(fd, in, sizeof in);
    if (got <= 0) break;
    for (ssize_t i = 0; i < got; ++i)
      if (dec.push(in[i])) {
        p::dwell_msg d;
        if (dec.current().as(d)) out.dwells[dec.current().seq] = d;
      }
  }
  out.counts = dec.counts();
  close(fd);
  EXPECT_EQ(pclose(emu), 0);
  std::ifstream err(log + ".err");
  std::getline(err, out.summary);
  return out;
}

TEST(EmulateCli, AReaderOnThePtyGetsExactlyWhatTheDeviceSent) {
  gyroflip::test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv";
  const run_result r = emulate("", log, 120.0);
  const auto sent = read_log(log);
  ASSERT_GE(sent.size(), 100u) << r.summary;
  ASSERT_EQ(r.dwells.size(), sent.size()) << r.summary;
  for (const auto& [seq, row] : sent) {
    SCOPED_TRACE(seq);
    ASSERT_EQ(r.dwells.count(seq), 1u);
    EXPECT_EQ(fields(r.dwells.at(seq)), row.v);
    EXPECT_FALSE(row.hit);
  }
  EXPECT_EQ(r.counts.bad(), 0u);
  EXPECT_EQ(r.counts.missing, 0u);
}

// Bit flips at 1e-3 and byte drops at 1e-4 on the device's output: the line code corrects the
// flips (one per wire byte), a drop costs its frame; nothing arrives that differs from what was
// sent. (The recorder asks for the lost ones again: test_record_cli.cpp.)
TEST(EmulateCli, LinkFaultsAreCorrectedOrLoseTheirFrameAndNeverMisread) {
  gyroflip::test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv";
  const run_result r = emulate("--fault-ber 1e-3 --fault-drop 1e-4", log, 300.0);
  const auto sent = read_log(log);
  ASSERT_GE(sent.size(), 250u) << r.summary;
  size_t hit = 0, lost = 0;
  for (const auto& [seq, row] : sent) {
    SCOPED_TRACE(seq);
    hit += row.hit ? 1 : 0;
    const auto it = r.dwells.find(seq);
    if (it == r.dwells.end()) {
      ++lost;
      continue;
    }
    EXPECT_EQ(fields(it->second), row.v);
  }
  // A DWELL is ~124 wire bytes: ~63 % of them meet a flipped bit at 1e-3 and nearly all of
  // those are corrected; ~1.2 % meet a dropped byte.
  EXPECT_GT(hit, sent.size() / 3) << r.summary;
  EXPECT_LT(lost, sent.size() / 20) << r.summary;
  EXPECT_LT(lost, hit / 10);
  EXPECT_EQ(r.dwells.size(), sent.size() - lost);
}

}  // namespace
