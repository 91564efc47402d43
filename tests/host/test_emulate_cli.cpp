// `gyroflip emulate` through a real pseudo-terminal (issue 9): what a reader decodes is what the
// device sent (its --log), and link faults lose exactly the frames they hit; its --log and --link
// never destroy a file of the user's (issue 21).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "firmware/protocol/frame.hpp"
#include "firmware/protocol/line.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace p = gyroflip::protocol;
namespace fs = std::filesystem;
using gyroflip::test::read_text;
using gyroflip::test::run_cli;
using gyroflip::test::write_text;

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
    EXPECT_EQ(cells.size(), 20u) << line;
    EXPECT_EQ(cells[19], "1") << line;  // the first boot: no reset in these runs
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

// Issue 21: `--temp-profile p.csv --log p.csv` and `--sensor my.toml --log my.toml` truncated the
// input; the log was opened before later checks, so a refused run had truncated it already.
TEST(EmulateCli, TheLogNeverTruncatesAnInputOrARefusedRunsFile) {
  gyroflip::test::temp_dir dir;
  const std::string profile = dir.path() + "/p.csv", toml = dir.path() + "/my.toml";
  write_text(profile, "time_s,temp_c\n0,20\n100,21\n");
  write_text(toml, "not read: the log check comes first\n");
  fs::create_symlink("p.csv", dir.path() + "/link.csv");
  const std::vector<std::vector<std::string>> same_file{
      {"--temp-profile", profile, "--log", profile},
      {"--temp-profile", profile, "--log", dir.path() + "/link.csv"},
      {"--sensor", toml, "--log", toml},
  };
  for (const auto& extra : same_file) {
    std::vector<std::string> args{"emulate", "--pty", "--duration", "1", "--speed", "max"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << extra[0] << " " << extra[3];
    EXPECT_NE(r.err.find("is an input of this run"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");  // refused before the line was opened
  }
  EXPECT_EQ(read_text(profile), "time_s,temp_c\n0,20\n100,21\n");
  EXPECT_EQ(read_text(toml), "not read: the log check comes first\n");
  // A run refused for another reason leaves an existing log as it was.
  const std::string log = dir.path() + "/sent.csv", mine = dir.path() + "/mine.txt";
  write_text(log, "an earlier run's log\n");
  write_text(mine, "keep");
  for (const auto& extra : std::vector<std::vector<std::string>>{
           {"--link", mine}, {"--sensor", dir.path() + "/nope.toml"}, {"--fault-unplug", "5"}}) {
    std::vector<std::string> args{"emulate", "--pty", "--duration", "1", "--log", log};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << extra[0] << ": " << r.err;
    EXPECT_EQ(read_text(log), "an earlier run's log\n") << extra[0];
  }
  EXPECT_EQ(read_text(mine), "keep");
}

// Issue 21: `--link rig` unlinked a file named rig.new (its temporary name) before making the
// link; a symbolic link of the user's that points somewhere was replaced and, at the end, removed.
TEST(EmulateCli, TheLinkRemovesOnlyWhatItMade) {
  gyroflip::test::temp_dir dir;
  const std::string rig = dir.path() + "/rig";
  write_text(rig + ".new", "a file of the user's\n");
  const auto r = run_cli({"emulate", "--pty", "--duration", "2", "--speed", "max", "--link", rig});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("the rig is on " + rig), std::string::npos) << r.out;
  EXPECT_EQ(read_text(rig + ".new"), "a file of the user's\n");
  EXPECT_FALSE(fs::exists(fs::symlink_status(rig)));  // removed at the end: it was this run's
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir.path())) left.push_back(e.path().filename());
  EXPECT_EQ(left, std::vector<std::string>{"rig.new"});
  // A link of the user's pointing at something that exists stays, whatever it points at.
  write_text(dir.path() + "/target.txt", "t");
  fs::create_symlink("target.txt", rig);
  const auto mine = run_cli({"emulate", "--pty", "--duration", "1", "--link", rig});
  EXPECT_EQ(mine.exit_code, 2);
  EXPECT_NE(mine.err.find("which exists"), std::string::npos) << mine.err;
  EXPECT_EQ(fs::read_symlink(rig), "target.txt");
  // A dangling one (an emulator killed before it could remove its link) is taken over.
  fs::remove(rig);
  fs::create_symlink("/dev/pts/999999", rig);
  EXPECT_EQ(
      run_cli({"emulate", "--pty", "--duration", "1", "--speed", "max", "--link", rig}).exit_code,
      0);
  EXPECT_FALSE(fs::exists(fs::symlink_status(rig)));
}

}  // namespace
