// `gyroflip record` and `export` against `gyroflip emulate` on a pty (issue 9): the file holds
// exactly what the device sent, calibrates to the emulator's truth, survives faults, Ctrl-C and
// SIGKILL, and a damaged file is an error naming the record.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "firmware/protocol/frame.hpp"
#include "gyroflip/io/series.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "host/emulator/emulator.hpp"
#include "host/recorder/rig_run.hpp"
#include "support/pty_process.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace gyroflip;
namespace p = gyroflip::protocol;
using test::run_cli;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// `gyroflip emulate --pty ARGS` in the background; stopped by SIGTERM when it goes.
struct emulator_process : test::pty_process {
  emulator_process(const std::string& dir, const std::string& args)
      : test::pty_process(std::string(GYROFLIP_EXE) + " emulate --pty " + args, dir) {
    EXPECT_FALSE(pty().empty()) << output();
  }
};

struct sent_dwell {
  // seq,cycle,position,t_start,t_end,n,code_sum,...,flags,sent_time_s,hit,table_deg
  std::vector<std::string> cells;
  [[nodiscard]] long long at(std::size_t i) const { return std::stoll(cells[i]); }
  [[nodiscard]] double num(std::size_t i) const { return std::stod(cells[i]); }
  [[nodiscard]] bool hit() const { return cells[17] == "1"; }
  [[nodiscard]] double table_deg() const { return num(18); }
};

std::vector<sent_dwell> read_log(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<sent_dwell> rows;
  while (std::getline(in, line))
    if (auto c = split(line); c.size() == 19) rows.push_back({c});
  return rows;
}

// The emulator's defaults (cmd_emulate): the paper's rig with the HZ1-90-100A at its T_ref.
double scale_factor() {
  return sensor::find_builtin("hz1-90-100a")->params.scale_factor_v_per_dps;
}
constexpr double lsb_v = 5.0 / 16777216.0;  // AD7739 +-2.5 V over 2^24 codes

// `calibrate --json` of a recording from the emulator's defaults: its dN is the emulator's Earth
// term plus g-term within 4 sigma of the correlated standard error.
// `seed`: the emulator's --seed, which draws this power-up's g-term (its dN) as the run's did.
void expect_calibrates_to_truth(const nlohmann::json& j, std::uint64_t seed) {
  host::emulator_config c;
  c.sim.sensor = sensor::find_builtin("hz1-90-100a")->params;
  c.sim.seed = seed;
  c.sim.lat_deg = 42.6;
  c.sim.axis = "north";
  auto e = host::emulator::make(c);
  ASSERT_TRUE(e);
  const double truth = (*e)->delta_n_truth_dps(c.sim.sensor.temp_ref_c);
  const double se = j["stderr_correlated_dps"];
  EXPECT_NEAR(j["delta_n_dps"].get<double>(), truth, 4 * se) << "se " << se;
}

TEST(RecordCli, ExportEqualsWhatTheDeviceSentAndCalibratesToTheTruth) {
  test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv", gfr = dir.path() + "/run.gfr";
  emulator_process emu(dir.path(), "--speed max --seed 5 --log " + log);
  const auto rec = run_cli({"record", "--port", emu.pty(), "--duration", "600", "-o", gfr});
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  const auto ex = run_cli({"export", gfr, "-o", dir.path() + "/run.csv"});
  ASSERT_EQ(ex.exit_code, 0) << ex.err;
  EXPECT_EQ(ex.err, "");

  std::map<long long, sent_dwell> sent;  // by seq (no wrap in 600 s)
  for (auto& r : read_log(log)) sent[r.at(0)] = r;
  std::ifstream csv(dir.path() + "/run.csv");
  std::string line;
  while (std::getline(csv, line) && line.rfind('#', 0) == 0) {
  }
  ASSERT_EQ(line,
            "time_s,angle_deg,rate_dps,temp_c,n_avg,accel_x_g,accel_y_g,cycle,position,flags,"
            "segment,seq");
  const double sf = scale_factor();
  std::size_t rows = 0;
  long long last_seq = -1;
  std::vector<double> rate_column;
  while (std::getline(csv, line)) {
    const auto c = split(line);
    ASSERT_EQ(c.size(), 12u) << line;
    const long long seq = std::stoll(c[11]);
    ASSERT_EQ(sent.count(seq), 1u) << line;
    const auto& s = sent.at(seq);
    SCOPED_TRACE(line);
    EXPECT_EQ(std::stoll(c[7]), s.at(1));  // cycle
    EXPECT_EQ(std::stoll(c[8]), s.at(2));  // position
    EXPECT_EQ(std::stod(c[1]), s.at(2) == 0 ? 0.0 : 180.0);
    EXPECT_EQ(std::stoll(c[4]), s.at(5));  // n
    EXPECT_DOUBLE_EQ(std::stod(c[2]), s.num(6) / s.num(5) * lsb_v / sf);
    EXPECT_DOUBLE_EQ(std::stod(c[3]), s.num(10) / s.num(9) * lsb_v / 8.4e-3 + 24.85);
    EXPECT_EQ(std::stoll(c[9]), s.at(15));  // flags
    if (rows == 0) {
      // The first DWELL of the run (the device may send it right behind START's ACK).
      EXPECT_EQ(c[7], "0");
      EXPECT_EQ(c[8], "0");
    }
    EXPECT_GT(seq, last_seq);
    last_seq = seq;
    rate_column.push_back(std::stod(c[2]));
    ++rows;
  }
  // The same rows as HDF5 datasets (export -o RUN.h5).
  const std::string h5 = dir.path() + "/run.h5";
  const auto ex5 = run_cli({"export", gfr, "-o", h5});
  ASSERT_EQ(ex5.exit_code, 0) << ex5.err;
  io::series_options so;
  so.sample_rate_hz = 1.0;
  so.dataset = "/rate_dps";
  auto rate = io::read_series(h5, so);
  ASSERT_TRUE(rate) << rate.err().message;
  ASSERT_EQ(rate->values().size(), rate_column.size());
  for (std::size_t i = 0; i < rate_column.size(); ++i) EXPECT_EQ(rate->values()[i], rate_column[i]);
  // 600 s of ~0.97-s dwells: every DWELL sent before STOP is in the file, none twice.
  std::size_t sent_before = 0;
  for (const auto& [seq, s] : sent) sent_before += seq <= last_seq ? 1 : 0;
  EXPECT_EQ(rows, sent_before);
  EXPECT_GE(rows, 600u);

  // calibrate on the .gfr: the emulator's Earth term plus g-term within 4 sigma.
  const auto cal = run_cli({"calibrate", gfr, "--json"});
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  expect_calibrates_to_truth(nlohmann::json::parse(cal.out), 5);
}

TEST(RecordCli, RawConversionsSumToTheirDwellsAndExportOneRowEach) {
  test::temp_dir dir;
  const std::string gfr = dir.path() + "/raw.gfr";
  {
    emulator_process emu(dir.path(), "--speed max --seed 4");
    const auto rec =
        run_cli({"record", "--port", emu.pty(), "--duration", "30", "--raw", "-o", gfr});
    ASSERT_EQ(rec.exit_code, 0) << rec.err;
  }
  auto run = host::read_rig_run(gfr, true);
  ASSERT_TRUE(run) << run.err().message;
  ASSERT_GE(run->dwells.size(), 25u);
  ASSERT_EQ(run->conversions.size(), run->dwells.size() * 256);
  // Only the dwell the end of the run cut short may leave RAW codes without their DWELL (the
  // device got STOP mid-dwell; at --speed max its first RAW blocks may already be in): fewer
  // than one dwell's 256.
  EXPECT_LT(run->unplaced_conversions, 256u);
  for (std::size_t k = 0; k < run->dwells.size(); ++k) {
    const auto& d = run->dwells[k];
    std::int64_t sum = 0;
    for (std::size_t i = 0; i < 256; ++i) {
      const auto& c = run->conversions[k * 256 + i];
      sum += c.code;
      EXPECT_EQ(c.angle_deg, d.angle_deg);
    }
    EXPECT_EQ(sum, d.d.code_sum) << k;
    // The dwell's time is the middle of its conversions' span.
    EXPECT_LT(run->conversions[k * 256].time_s, d.time_s);
    EXPECT_GT(run->conversions[k * 256 + 255].time_s, d.time_s);
  }
  const auto ex = run_cli({"export", gfr, "--raw", "-o", dir.path() + "/raw.csv"});
  ASSERT_EQ(ex.exit_code, 0) << ex.err;
  const std::string csv = test::read_text(dir.path() + "/raw.csv");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')),
            run->conversions.size() + 1 + host::csv_metadata(*run).size());
}

TEST(RecordCli, LinkFaultsBecomeGapRecordsNeverData) {
  test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv", gfr = dir.path() + "/run.gfr";
  emulator_process emu(dir.path(),
                       "--speed max --seed 7 --fault-ber 1e-3 --fault-drop 1e-4 --log " + log);
  const auto rec = run_cli({"record", "--port", emu.pty(), "--duration", "300", "-o", gfr});
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  auto run = host::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  std::map<long long, sent_dwell> sent;
  for (auto& r : read_log(log)) sent[r.at(0)] = r;
  std::set<long long> stored;
  for (const auto& d : run->dwells) {
    SCOPED_TRACE(d.seq);
    ASSERT_EQ(sent.count(d.seq), 1u);
    const auto& s = sent.at(d.seq);
    EXPECT_FALSE(s.hit()) << "a frame a fault hit was stored";
    EXPECT_EQ(d.d.code_sum, s.at(6));
    EXPECT_EQ(d.d.t_start_ticks, static_cast<std::uint32_t>(s.at(3)));
    stored.insert(d.seq);
  }
  // Between the first and last stored DWELL: what was lost is what a fault hit, plus at most
  // the frames merged with a hit one through a damaged delimiter.
  std::size_t hit = 0, lost = 0;
  for (auto it = sent.lower_bound(*stored.begin());
       it != sent.end() && it->first <= *stored.rbegin(); ++it) {
    hit += it->second.hit() ? 1U : 0U;
    lost += stored.count(it->first) == 0 ? 1U : 0U;
  }
  EXPECT_GT(hit, 50u);
  EXPECT_GE(lost, hit);
  EXPECT_LE(lost, hit + hit / 4 + 2);
  // Every lost frame is a skipped sequence number; each hit frame also leaves a corrupt one
  // (unless the fault dropped its delimiter and merged it with the next).
  EXPECT_GE(run->missing_frames, lost);
  EXPECT_GE(run->corrupt_frames, hit / 2);
  EXPECT_EQ(run->stop, host::gfr::stop_reason::duration);
}

// The log's DWELLs by their start tick (the emulator's clock never restarts, its sequence
// numbers do after a reset).
std::map<long long, sent_dwell> sent_by_start(const std::string& log) {
  std::map<long long, sent_dwell> sent;
  for (auto& r : read_log(log)) sent[r.at(3)] = r;
  return sent;
}

// Every stored DWELL is one the device sent, unharmed; every one the device sent unharmed
// between the first and the last stored is stored. Returns how many sent ones were lost.
std::size_t expect_stored_is_what_was_sent(const host::rig_run& run,
                                           const std::map<long long, sent_dwell>& sent) {
  std::set<long long> stored;
  for (const auto& d : run.dwells) {
    SCOPED_TRACE(d.d.t_start_ticks);
    const auto it = sent.find(d.d.t_start_ticks);
    if (it == sent.end()) {
      ADD_FAILURE() << "a stored DWELL the device never sent";
      continue;
    }
    EXPECT_FALSE(it->second.hit());
    EXPECT_EQ(d.d.code_sum, it->second.at(6));
    EXPECT_EQ(d.d.position, it->second.at(2));
    stored.insert(d.d.t_start_ticks);
  }
  std::size_t lost = 0;
  if (stored.empty()) return lost;
  for (auto it = sent.find(*stored.begin()); it != sent.end() && it->first <= *stored.rbegin();
       ++it) {
    if (it->second.hit())
      ++lost;
    else
      EXPECT_EQ(stored.count(it->first), 1u) << "sent unharmed, not stored: tick " << it->first;
  }
  return lost;
}

TEST(RecordCli, ADeviceResetIsRecordedAndTheRunGoesOnWithTheTableHomed) {
  test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv", gfr = dir.path() + "/run.gfr";
  // Three resets, 150-s apart at odd times: at least one falls while the table is at B.
  emulator_process emu(dir.path(),
                       "--speed max --seed 13 --fault-reset-at 150.3,300.9,451.7 --log " + log);
  const auto rec = run_cli({"record", "--port", emu.pty(), "--duration", "600", "-o", gfr});
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  // Each reset: a device-reset gap, the device's INFO, a CONFIGURE that finds the home switch
  // first, START.
  auto f = host::gfr::read(gfr);
  ASSERT_TRUE(f) << f.err().message;
  std::vector<host::gfr::kind> after;
  int resets = 0;
  for (std::size_t i = 0; i < f->records.size(); ++i) {
    const auto& r = f->records[i];
    if (r.type != host::gfr::kind::gap ||
        r.body.at(0) != static_cast<std::uint8_t>(host::gfr::gap_reason::device_reset))
      continue;
    ++resets;
    std::vector<const host::gfr::record*> next;
    for (std::size_t k = i + 1; k < f->records.size() && next.size() < 3; ++k)
      if (f->records[k].type != host::gfr::kind::frame) next.push_back(&f->records[k]);
    ASSERT_EQ(next.size(), 3u);
    EXPECT_EQ(next[0]->type, host::gfr::kind::info);
    ASSERT_EQ(next[1]->type, host::gfr::kind::configure);
    EXPECT_EQ(next[2]->type, host::gfr::kind::start);
    const p::frame fr{static_cast<std::uint8_t>(p::msg::configure), 0, next[1]->body.data(),
                      next[1]->body.size()};
    p::configure_msg c;
    ASSERT_TRUE(fr.as(c));
    EXPECT_NE(c.flags & p::cfg_home, 0) << "a rebooted device must find the table's home";
  }
  EXPECT_EQ(resets, 3);
  auto run = host::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  EXPECT_EQ(run->device_resets, 3u);
  EXPECT_EQ(run->link_losses, 0u);
  ASSERT_FALSE(run->dwells.empty());
  EXPECT_EQ(run->dwells.back().segment, 3u);
  const auto sent = sent_by_start(log);
  EXPECT_EQ(expect_stored_is_what_was_sent(*run, sent), 0u);
  // Where the table truly stood: the position each DWELL names (the reset device homed it).
  for (const auto& [tick, s] : sent) EXPECT_EQ(s.table_deg(), 180.0 * s.num(2)) << "tick " << tick;
  const auto cal = run_cli({"calibrate", gfr, "--json"});
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  expect_calibrates_to_truth(nlohmann::json::parse(cal.out), 13);
}

TEST(RecordCli, AnUnpluggedAdapterIsWaitedForAndTheRunResumesWithAGapRecord) {
  test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv", gfr = dir.path() + "/run.gfr";
  const std::string link = dir.path() + "/rig";  // like /dev/serial/by-id/...
  emulator_process emu(
      dir.path(), "--speed 100 --seed 17 --fault-unplug 120:1.5 --link " + link + " --log " + log);
  ASSERT_EQ(emu.pty(), link);
  const auto rec = run_cli(
      {"record", "--port", link, "--duration", "400", "--reconnect-timeout", "20", "-o", gfr});
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  auto f = host::gfr::read(gfr);
  ASSERT_TRUE(f) << f.err().message;
  int gaps = 0;
  for (const auto& r : f->records)
    if (r.type == host::gfr::kind::gap &&
        r.body.at(0) == static_cast<std::uint8_t>(host::gfr::gap_reason::link_lost)) {
      ++gaps;
      p::reader rd{r.body.data() + 1, 4};
      const std::uint32_t ms = rd.u32();
      EXPECT_GE(ms, 1000u);  // 1.5 s unplugged, noticed at once or nearly
      EXPECT_LE(ms, 20000u);
    }
  EXPECT_EQ(gaps, 1);
  auto run = host::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  EXPECT_EQ(run->link_losses, 1u);
  EXPECT_EQ(run->device_resets, 0u);  // the rig ran on: no new configuration
  EXPECT_EQ(run->stop, host::gfr::stop_reason::duration);
  // Lost: what the rig sent while the line was gone (1.5 s at 100x: ~150 DWELLs); nothing else.
  const std::size_t lost = expect_stored_is_what_was_sent(*run, sent_by_start(log));
  EXPECT_GT(lost, 80u);
  EXPECT_GT(run->dwells.size(), 200u);
}

TEST(RecordCli, APortThatStaysAwayEndsTheRunWithACompleteFile) {
  test::temp_dir dir;
  const std::string gfr = dir.path() + "/run.gfr", link = dir.path() + "/rig";
  emulator_process emu(dir.path(), "--speed 100 --seed 19 --fault-unplug 60:4 --link " + link);
  const auto rec = run_cli(
      {"record", "--port", link, "--duration", "400", "--reconnect-timeout", "1", "-o", gfr});
  EXPECT_EQ(rec.exit_code, 1);
  EXPECT_NE(rec.err.find("did not come back within 1 s"), std::string::npos) << rec.err;
  auto run = host::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  EXPECT_TRUE(run->warnings.empty());
  EXPECT_EQ(run->stop, host::gfr::stop_reason::link_lost);
  EXPECT_EQ(run->link_losses, 1u);
  EXPECT_GT(run->dwells.size(), 40u);  // the 60 s before the loss
}

TEST(RecordCli, EmulatorFaultOptionsAreCheckedAndItsLinkNeverReplacesAFile) {
  test::temp_dir dir;
  const std::string mine = dir.path() + "/mine.txt";
  std::ofstream(mine) << "keep";
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"--fault-unplug", "5"},
                                              {"--fault-unplug", "5:0"},
                                              {"--fault-unplug", "x:1"},
                                              {"--fault-reset-at", "-1"},
                                              {"--fault-reset-at", "nan"},
                                              {"--link", mine}}) {
    std::vector<std::string> args{"emulate", "--pty", "--duration", "1"};
    args.insert(args.end(), bad.begin(), bad.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << bad[0] << " " << bad[1];
    EXPECT_EQ(r.out, "") << bad[1];  // refused before the line was opened
  }
  EXPECT_EQ(test::read_text(mine), "keep");
}

TEST(RecordCli, CtrlCStopsTheDeviceAndLeavesACompleteFile) {
  test::temp_dir dir;
  const std::string gfr = dir.path() + "/run.gfr";
  emulator_process emu(dir.path(), "--speed 50 --seed 3");
  const int pid = test::spawn_cli({"record", "--port", emu.pty(), "-o", gfr});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  kill(pid, SIGINT);
  EXPECT_EQ(test::wait_cli(pid), 0);
  auto f = host::gfr::read(gfr);
  ASSERT_TRUE(f) << f.err().message;
  EXPECT_TRUE(f->warnings.empty());
  ASSERT_EQ(f->records.back().type, host::gfr::kind::stop);
  EXPECT_EQ(f->records.back().body.at(0),
            static_cast<std::uint8_t>(host::gfr::stop_reason::signal));
  // The device answered the STOP with a STATUS that says idle.
  std::optional<p::status_msg> last;
  for (const auto& r : f->records) {
    if (r.type != host::gfr::kind::frame || r.body[0] != static_cast<std::uint8_t>(p::msg::status))
      continue;
    const p::frame fr{r.body[0], 0, r.body.data() + 3, r.body.size() - 3};
    p::status_msg s;
    ASSERT_TRUE(fr.as(s));
    last = s;
  }
  ASSERT_TRUE(last);
  EXPECT_EQ(last->state, static_cast<std::uint8_t>(p::device_state::idle));
  auto run = host::read_rig_run(gfr);
  ASSERT_TRUE(run);
  EXPECT_GT(run->dwells.size(), 20u);  // 1.5 s at 50x
}

// SIGKILL at 10 random moments: every file reads back, and every DWELL the emulator logged as
// sent more than 1.5 s before the kill is in it.
TEST(RecordCli, SigkillAtRandomMomentsLosesNothingSentBeforeIt) {
  test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv";
  emulator_process emu(dir.path(), "--speed 100 --seed 11 --log " + log);
  std::mt19937 rng(20261123);
  std::uniform_int_distribution<int> wait_ms(200, 900);
  for (int k = 0; k < 10; ++k) {
    SCOPED_TRACE(k);
    const std::string gfr = dir.path() + "/run" + std::to_string(k) + ".gfr";
    const std::size_t before = read_log(log).size();
    const int pid = test::spawn_cli({"record", "--port", emu.pty(), "-o", gfr});
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms(rng)));
    // Sent by now, in this recorder's run: the rows after the first cycle-0 A dwell it started.
    const auto rows = read_log(log);
    std::set<long long> must;
    bool in_run = false;
    for (std::size_t i = before; i < rows.size(); ++i) {
      in_run = in_run || (rows[i].at(1) == 0 && rows[i].at(2) == 0);
      if (in_run) must.insert(rows[i].at(3));  // t_start_ticks
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    kill(pid, SIGKILL);
    EXPECT_EQ(test::wait_cli(pid), 128 + SIGKILL);
    auto run = host::read_rig_run(gfr);
    ASSERT_TRUE(run) << run.err().message;
    std::set<long long> have;
    for (const auto& d : run->dwells) have.insert(d.d.t_start_ticks);
    EXPECT_GT(must.size(), 5u);
    for (const long long t : must) EXPECT_EQ(have.count(t), 1u) << "DWELL at tick " << t;
  }
}

TEST(RecordCli, ADamagedFileIsAnErrorNamingTheRecordAndWritesNothing) {
  test::temp_dir dir;
  const std::string good = dir.path() + "/good.gfr";
  {
    emulator_process emu(dir.path(), "--speed max --seed 2");
    ASSERT_EQ(run_cli({"record", "--port", emu.pty(), "--duration", "20", "-o", good}).exit_code,
              0);
  }
  const std::string whole = test::read_text(good);
  ASSERT_GT(whole.size(), 400u);
  struct damage {
    std::string name, bytes, says;
  };
  std::string flipped_header = whole, magic = whole, future = whole, flipped_body = whole;
  flipped_header[9] = static_cast<char>(flipped_header[9] ^ 0x10);
  magic[0] = 'G';
  future[8] = 9;  // version 9 (its header checksum no longer matches either: both are named)
  flipped_body[200] = static_cast<char>(flipped_body[200] ^ 0x01);
  const std::vector<damage> cases = {
      {"truncated", whole.substr(0, 11), "record 0: the file header is cut short"},
      {"flipped_header", flipped_header, "record 0: file header checksum mismatch"},
      {"magic", magic, "record 0: not a gyroflip rig recording"},
      {"future", future, "record 0: file header checksum mismatch"},
      {"flipped_body", flipped_body, ": checksum mismatch (the file is damaged)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir.path() + "/" + c.name + ".gfr";
    const std::string out = dir.path() + "/" + c.name + ".csv";
    test::write_text(path, c.bytes);
    for (const auto& cmd : {std::vector<std::string>{"export", path, "-o", out},
                            std::vector<std::string>{"calibrate", path, "-o", out}}) {
      const auto r = run_cli(cmd);
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_NE(r.err.find(path + ": record "), std::string::npos) << r.err;
      EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
      EXPECT_FALSE(test::exists(out));
    }
  }
  // A torn last record (a killed recorder): read, with a warning naming it.
  const std::string torn = dir.path() + "/torn.gfr";
  test::write_text(torn, whole.substr(0, whole.size() - 3));
  const auto r = run_cli({"export", torn, "-o", dir.path() + "/torn.csv"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("cut off while it was written"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no STOP record"), std::string::npos) << r.err;
}

}  // namespace
