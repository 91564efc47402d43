// `gyroflip record` and `export` against `gyroflip emulate` on a pty (issue 9): the file holds
// exactly what the device sent, calibrates to the emulator's truth, survives faults, Ctrl-C and
// SIGKILL, and a damaged file is an error naming the record.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "firmware/protocol/frame.hpp"
#include "gyroflip/io/series.hpp"
#include "gyroflip/rigdata/rig_run.hpp"
#include "gyroflip/sensor/presets.hpp"
#include "host/emulator/emulator.hpp"
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

// A recording of the emulator is not a measurement (issue 22 §3, review R6): the emulator says
// what it is in INFO, the file keeps it, and the report shows the "Simulated data" banner and the
// origin "emulated" (as it does for a CSV exported from the file).
TEST(RecordCli, AnEmulatorsRecordingIsReportedAsSimulated) {
  test::temp_dir dir;
  const std::string gfr = dir.path() + "/run1.gfr";
  emulator_process emu(dir.path(), "--speed max --seed 21 --serial 4711");
  const auto rec = run_cli({"record", "--port", emu.pty(), "--duration", "120", "-o", gfr});
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  const auto ex = run_cli({"export", gfr, "-o", dir.path() + "/run1.csv"});
  ASSERT_EQ(ex.exit_code, 0) << ex.err;
  for (const std::string& in : {gfr, dir.path() + "/run1.csv"}) {
    SCOPED_TRACE(in);
    const std::string out = dir.path() + "/rep" + std::to_string(in.size());
    const auto rep = run_cli({"report", in, "-o", out});
    ASSERT_EQ(rep.exit_code, 0) << rep.err;
    const std::string html = test::read_text(out + "/index.html");
    EXPECT_NE(html.find("Simulated data: 1 of the 1 recordings came from gyroflip's emulator"),
              std::string::npos);
    EXPECT_NE(html.find("emulated: a rig recording"), std::string::npos);
    EXPECT_NE(html.find("emulated (gyroflip emulate: no real board)"), std::string::npos);
  }
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
  auto run = rigdata::read_rig_run(gfr, true);
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
            run->conversions.size() + 1 + rigdata::csv_metadata(*run).size());
}

// Under ASan the suite runs ~5x slower: the long figure runs are shortened there (the CI's
// release run has the full ones; docs/RELIABILITY.md has the figures).
#if defined(__SANITIZE_ADDRESS__)
constexpr double figure_s = 120;
#else
constexpr double figure_s = 600;
#endif

// The log's DWELLs by their start tick (the emulator's clock never restarts, its sequence
// numbers do after a reset).
std::map<long long, sent_dwell> sent_by_start(const std::string& log) {
  std::map<long long, sent_dwell> sent;
  for (auto& r : read_log(log)) sent[r.at(3)] = r;
  return sent;
}

// What a recording holds against what the device sent: every stored DWELL is one the device
// sent, unharmed, labelled with the angle the table truly stood at; `lost` counts those the
// device sent (from its run's first cycle-0 A dwell to the last stored one) that are not stored.
struct comparison {
  std::size_t sent = 0, stored = 0, lost = 0, mislabelled = 0, lost_not_hit = 0;
};
comparison compare(const rigdata::rig_run& run, const std::map<long long, sent_dwell>& sent) {
  comparison c;
  std::set<long long> stored;
  for (const auto& d : run.dwells) {
    SCOPED_TRACE(d.d.t_start_ticks);
    const auto it = sent.find(d.d.t_start_ticks);
    if (it == sent.end()) {
      ADD_FAILURE() << "a stored DWELL the device never sent";
      continue;
    }
    EXPECT_EQ(d.d.code_sum, it->second.at(6));
    EXPECT_EQ(d.d.position, it->second.at(2));
    if (std::fabs(d.angle_deg - it->second.table_deg()) > 1e-9) ++c.mislabelled;
    stored.insert(d.d.t_start_ticks);
  }
  c.stored = stored.size();
  if (stored.empty()) return c;
  auto first = sent.begin();
  while (first != sent.end() && !(first->second.at(1) == 0 && first->second.at(2) == 0)) ++first;
  for (auto it = first; it != sent.end() && it->first <= *stored.rbegin(); ++it) {
    ++c.sent;
    if (stored.count(it->first) == 0) {
      ++c.lost;
      if (!it->second.hit()) ++c.lost_not_hit;
    }
  }
  return c;
}

std::string recorded(const comparison& c) {
  return std::to_string(c.stored) + " of " + std::to_string(c.sent) + " DWELLs recorded, " +
         std::to_string(c.lost) + " lost";
}

// The figures (docs/RELIABILITY.md): dwells recorded of dwells sent, 10 simulated minutes
// at --speed max, per fault. The line code corrects single flips, RESEND brings back what was
// still lost while the device has it; what it no longer has is a gap record with its count.
struct figure {
  std::string faults;
  double min_recorded;
};
class LinkFigures : public ::testing::TestWithParam<figure> {};

TEST_P(LinkFigures, DwellsRecordedOfDwellsSent) {
  test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv", gfr = dir.path() + "/run.gfr";
  emulator_process emu(dir.path(), "--speed max --seed 21 " + GetParam().faults + " --log " + log);
  const auto rec =
      run_cli({"record", "--port", emu.pty(), "--duration", std::to_string(figure_s), "-o", gfr});
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  auto run = rigdata::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  const comparison c = compare(*run, sent_by_start(log));
  RecordProperty("recorded", recorded(c));
  std::printf("%s: %s\n", GetParam().faults.c_str(), recorded(c).c_str());
  EXPECT_GE(c.sent, static_cast<std::size_t>(figure_s / 1.0));
  EXPECT_GE(static_cast<double>(c.stored), GetParam().min_recorded * static_cast<double>(c.sent))
      << recorded(c) << "\n"
      << rec.err;
  EXPECT_EQ(c.mislabelled, 0u);
  // The run's own count of lost dwells is the truth's, and each one is in a gap record.
  EXPECT_EQ(run->lost_dwells, c.lost);
  EXPECT_GE(run->missing_frames, c.lost);
  EXPECT_EQ(run->outside_runs, 0u);
  // The first dwell (cycle 0 at A) is there, whenever START's ACK came.
  ASSERT_FALSE(run->dwells.empty());
  EXPECT_EQ(run->dwells.front().d.cycle, 0u);
  EXPECT_EQ(run->dwells.front().d.position, 0u);
}

std::string figure_name(const ::testing::TestParamInfo<figure>& info) {
  static const char* const names[] = {"clean", "ber_1e3", "ber_5e3", "ber_1e2", "drop_1e2"};
  return names[info.index];
}

INSTANTIATE_TEST_SUITE_P(Faults, LinkFigures,
                         ::testing::Values(figure{"", 1.0}, figure{"--fault-ber 1e-3", 1.0},
                                           figure{"--fault-ber 5e-3", 0.999},
                                           figure{"--fault-ber 1e-2", 0.99},
                                           figure{"--fault-drop 1e-2", 0.99}),
                         figure_name);

// An unplugged adapter for 3 s of the rig's time: the recorder finds the line again and asks for
// what the rig sent meanwhile; all of it is still in the device's history (6 s).
TEST(RecordCli, AThreeSecondUnplugLosesNothing) {
  test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv", gfr = dir.path() + "/run.gfr";
  const std::string link = dir.path() + "/rig";
  emulator_process emu(dir.path(),
                       "--speed 5 --seed 23 --fault-unplug 20:3 --link " + link + " --log " + log);
  const auto rec = run_cli(
      {"record", "--port", link, "--duration", "60", "--reconnect-timeout", "20", "-o", gfr});
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  auto run = rigdata::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  EXPECT_EQ(run->link_losses, 1u);
  const comparison c = compare(*run, sent_by_start(log));
  std::printf("unplug 3 s: %s\n", recorded(c).c_str());
  EXPECT_EQ(c.lost, 0u) << recorded(c);
  EXPECT_GT(c.stored, 50u);
  EXPECT_EQ(run->lost_dwells, 0u);
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
  auto f = rigdata::gfr::read(gfr);
  ASSERT_TRUE(f) << f.err().message;
  int resets = 0;
  for (std::size_t i = 0; i < f->records.size(); ++i) {
    const auto& r = f->records[i];
    if (r.type != rigdata::gfr::kind::gap ||
        r.body.at(0) != static_cast<std::uint8_t>(rigdata::gfr::gap_reason::device_reset))
      continue;
    ++resets;
    std::vector<const rigdata::gfr::record*> next;
    for (std::size_t k = i + 1; k < f->records.size() && next.size() < 3; ++k) {
      const auto type = f->records[k].type;
      if (type == rigdata::gfr::kind::frame || type == rigdata::gfr::kind::gap) continue;
      // A slow answer under load makes the recorder ask for INFO again: each answer is
      // recorded (a fresh Debian 12 run under load had two), one INFO is what is checked.
      if (type == rigdata::gfr::kind::info && !next.empty() &&
          next.back()->type == rigdata::gfr::kind::info)
        continue;
      next.push_back(&f->records[k]);
    }
    ASSERT_EQ(next.size(), 3u);
    EXPECT_EQ(next[0]->type, rigdata::gfr::kind::info);
    ASSERT_EQ(next[1]->type, rigdata::gfr::kind::configure);
    EXPECT_EQ(next[2]->type, rigdata::gfr::kind::start);
    const p::frame fr{static_cast<std::uint8_t>(p::msg::configure), 0, next[1]->body.data(),
                      next[1]->body.size()};
    p::configure_msg c;
    ASSERT_TRUE(fr.as(c));
    EXPECT_NE(c.flags & p::cfg_home, 0) << "a rebooted device must find the table's home";
  }
  EXPECT_EQ(resets, 3);
  auto run = rigdata::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  EXPECT_EQ(run->device_resets, 3u);
  EXPECT_EQ(run->link_losses, 0u);
  ASSERT_FALSE(run->dwells.empty());
  EXPECT_EQ(run->dwells.back().segment, 3u);
  const comparison c = compare(*run, sent_by_start(log));
  EXPECT_EQ(c.mislabelled, 0u);
  EXPECT_EQ(c.lost_not_hit, 0u) << recorded(c);
  const auto cal = run_cli({"calibrate", gfr, "--json"});
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  expect_calibrates_to_truth(nlohmann::json::parse(cal.out), 13);
}

// The review's reset storm (docs/RELIABILITY.md): resets at any moment - during a START retry,
// while the recorder waits for an ACK, mid-run - on a noisy line. Not one dwell may carry an
// angle other than where the table truly stood (the emulator's table_deg).
TEST(RecordCli, ResetStormsNeverMislabelADwell) {
  const std::vector<std::uint64_t> seeds = {10934, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    SCOPED_TRACE(seeds[k]);
    test::temp_dir dir;
    const std::string log = dir.path() + "/sent.csv", gfr = dir.path() + "/run.gfr";
    // The review's command for its seed; the others at full speed.
    const std::string speed = k == 0 ? "100" : "max";
    emulator_process emu(dir.path(), "--speed " + speed + " --seed " + std::to_string(seeds[k]) +
                                         " --fault-ber 1e-3 --fault-reset-at "
                                         "30,60.5,90,150,200,300,400 --log " +
                                         log);
    const auto rec = run_cli({"record", "--port", emu.pty(), "--duration", "450", "-o", gfr});
    ASSERT_EQ(rec.exit_code, 0) << rec.err;
    auto run = rigdata::read_rig_run(gfr);
    ASSERT_TRUE(run) << run.err().message;
    const comparison c = compare(*run, sent_by_start(log));
    EXPECT_EQ(c.mislabelled, 0u) << recorded(c);
    EXPECT_GE(run->device_resets, 7u);
    EXPECT_GT(c.stored, 300u) << recorded(c);
  }
}

TEST(RecordCli, APortThatStaysAwayEndsTheRunWithACompleteFile) {
  test::temp_dir dir;
  const std::string gfr = dir.path() + "/run.gfr", link = dir.path() + "/rig";
  emulator_process emu(dir.path(), "--speed 100 --seed 19 --fault-unplug 60:400 --link " + link);
  const auto rec = run_cli(
      {"record", "--port", link, "--duration", "400", "--reconnect-timeout", "1", "-o", gfr});
  EXPECT_EQ(rec.exit_code, 1);
  EXPECT_NE(rec.err.find("did not come back within 1 s"), std::string::npos) << rec.err;
  auto run = rigdata::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  EXPECT_TRUE(run->warnings.empty());
  EXPECT_EQ(run->stop, rigdata::gfr::stop_reason::link_lost);
  EXPECT_EQ(run->link_losses, 1u);
  EXPECT_GT(run->dwells.size(), 40u);  // the 60 s before the loss
}

// After the line comes back, another board answers (another serial): it is not recorded into the
// same file; the file is complete up to there.
TEST(RecordCli, AnotherDeviceAfterAReconnectIsRefused) {
  test::temp_dir dir;
  const std::string gfr = dir.path() + "/run.gfr", link = dir.path() + "/rig";
  auto first = std::make_unique<emulator_process>(dir.path(),
                                                  "--speed 20 --seed 29 --serial 7 --link " + link);
  const int pid = test::spawn_cli(
      {"record", "--port", link, "--duration", "600", "--reconnect-timeout", "20", "-o", gfr});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  first.reset();  // the first board goes
  emulator_process second(dir.path(), "--speed 20 --seed 30 --serial 8 --link " + link);
  EXPECT_EQ(test::wait_cli(pid), 1);
  auto run = rigdata::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  EXPECT_EQ(run->info.serial, 7u);
  EXPECT_GT(run->dwells.size(), 5u);
  EXPECT_EQ(run->stop, rigdata::gfr::stop_reason::device_changed);
}

// One recorder per port: a second one is refused at once, and the first records on, losing
// nothing.
TEST(RecordCli, ASecondRecorderOnThePortIsRefusedAndTheFirstLosesNothing) {
  test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv", gfr = dir.path() + "/one.gfr";
  emulator_process emu(dir.path(), "--speed 20 --seed 31 --log " + log);
  const int pid = test::spawn_cli({"record", "--port", emu.pty(), "--duration", "60", "-o", gfr});
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  const auto t0 = std::chrono::steady_clock::now();
  const auto second = run_cli({"record", "--port", emu.pty(), "-o", dir.path() + "/two.gfr"});
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(2));
  EXPECT_EQ(second.exit_code, 1) << second.err;
  EXPECT_NE(second.err.find("in use by another program"), std::string::npos) << second.err;
  EXPECT_FALSE(test::exists(dir.path() + "/two.gfr"));
  EXPECT_EQ(test::wait_cli(pid), 0);
  auto run = rigdata::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  const comparison c = compare(*run, sent_by_start(log));
  EXPECT_EQ(c.lost, 0u) << recorded(c);
  EXPECT_GT(c.stored, 40u);
}

// Runs `sh -c` with a small tmpfs of `size` bytes mounted at `mnt` (a private mount namespace),
// then `body`; where mounting is not allowed (a container, a chroot without the right), `body` runs
// with the record's file size limited to the same size instead (prlimit, SIGXFSZ ignored): its
// writes then fail with EFBIG where the filesystem's fail with ENOSPC, the recorder's path is the
// same. `limited` tells which.
test::cli_result on_small_disk(const std::string& mnt, const std::string& size,
                               const std::string& prep, const std::string& body, bool& limited) {
  const std::string mounted =
      "mount -t tmpfs -o size=" + size + " tmpfs " + mnt + " || exit 77; " + prep + body;
  limited = false;
  for (const bool map_root : {true, false}) {
    std::vector<std::string> args = {"unshare", "--mount"};
    if (map_root) args.emplace_back("--map-root-user");
    args.insert(args.end(), {"sh", "-c", mounted});
    auto r = test::run_program(args);
    if (r.out.find("rc=") != std::string::npos) return r;
  }
  limited = true;
  std::string b = body;
  const std::string rec = std::string(GYROFLIP_EXE) + " record ";
  b.replace(b.find(rec), rec.size(), "prlimit --fsize=" + size + " " + rec);
  return test::run_program({"sh", "-c", "trap '' XFSZ; " + prep + b});
}

// A full disk (a 48 KiB filesystem the test makes): the run ends with exit 1 naming it, the
// device is stopped, and what was recorded reads back; a disk full from the start leaves no file.
TEST(RecordCli, AFullDiskEndsTheRunStopsTheDeviceAndLeavesNoEmptyFile) {
  test::temp_dir dir;
  const std::string mnt = dir.path() + "/small";
  ASSERT_EQ(::mkdir(mnt.c_str(), 0755), 0);
  emulator_process emu(dir.path(), "--speed max --seed 33");
  bool limited = false;
  const auto r = on_small_disk(
      mnt, "49152", "",
      std::string(GYROFLIP_EXE) + " record --port " + emu.pty() + " --raw --duration 3000 -o " +
          mnt + "/run.gfr; echo \"rc=$?\"; ls -l " + mnt + "; " + GYROFLIP_EXE + " export " + mnt +
          "/run.gfr -o " + dir.path() + "/run.csv; echo \"export=$?\"",
      limited);
  EXPECT_NE(r.out.find("rc=1"), std::string::npos) << r.out << r.err;
  EXPECT_NE(r.err.find(limited ? "File too large" : "No space left on device"), std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("export=0"), std::string::npos) << r.out << r.err;  // what fit reads back
  const std::string csv = test::read_text(dir.path() + "/run.csv");
  EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 5);
  // Full from the start: no file at all.
  const std::string fill = limited ? "rm -f " + mnt + "/run.gfr; "  // what the first run left
                                   : "head -c 16384 /dev/zero > " + mnt + "/filler; ";
  const auto f =
      on_small_disk(mnt, limited ? "0" : "16384", fill,
                    std::string(GYROFLIP_EXE) + " record --port " + emu.pty() +
                        " --duration 10 -o " + mnt + "/run.gfr; echo \"rc=$?\"; ls " + mnt,
                    limited);
  EXPECT_NE(f.out.find("rc=1"), std::string::npos) << f.out << f.err;
  EXPECT_EQ(f.out.find("run.gfr"), std::string::npos) << f.out;
}

TEST(RecordCli, RefusesWhatItCouldNotRecordOrReadBack) {
  test::temp_dir dir;
  for (const auto& [args, says] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"-o", "-"}, "a recording is a file"},
           {{"--baud", "0", "-o", "x.gfr"}, "--baud"},
           {{"--temp-at-0v", "5000", "-o", "x.gfr"}, "--temp-at-0v"},
           {{"--temp-mv-per-c", "0", "-o", "x.gfr"}, "--temp-mv-per-c"},
       }) {
    std::vector<std::string> cmd{"record", "--port", "/dev/null"};
    cmd.insert(cmd.end(), args.begin(), args.end());
    const auto r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, 2) << args[0];
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_FALSE(test::exists("x.gfr"));
  }
}

// The handshake's errors say what happened: Ctrl-C is an interruption, not a rig that does not
// answer; bytes that never make a valid frame are not "is the rig connected".
TEST(RecordCli, HandshakeErrorsSayWhatHappened) {
  test::temp_dir dir;
  {  // nothing answers; SIGINT during the handshake
    test::pty_process quiet(
        "python3 -c \"import os,pty,sys,time; m,s=pty.openpty(); "
        "print(os.ttyname(s), flush=True); time.sleep(30)\"",
        dir.path());
    ASSERT_FALSE(quiet.pty().empty()) << quiet.output();
    test::temp_dir out;
    const std::string gfr = out.path() + "/q.gfr";
    const int pid = test::spawn_cli({"record", "--port", quiet.pty(), "-o", gfr});
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    kill(pid, SIGINT);
    EXPECT_EQ(test::wait_cli(pid), 1);
    EXPECT_FALSE(test::exists(gfr));
  }
  {  // noise on the line
    test::pty_process noisy(
        "python3 -c \"import os,pty,sys,time,random; m,s=pty.openpty(); "
        "print(os.ttyname(s), flush=True); r=random.Random(1)\n"
        "while True:\n  os.write(m, bytes(r.randrange(256) for _ in range(64))); "
        "time.sleep(0.01)\"",
        dir.path());
    ASSERT_FALSE(noisy.pty().empty()) << noisy.output();
    const auto r = run_cli({"record", "--port", noisy.pty(), "-o", dir.path() + "/n.gfr"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("bytes arrive but no valid reply"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("is the rig connected"), std::string::npos) << r.err;
  }
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
  auto f = rigdata::gfr::read(gfr);
  ASSERT_TRUE(f) << f.err().message;
  EXPECT_TRUE(f->warnings.empty());
  ASSERT_EQ(f->records.back().type, rigdata::gfr::kind::stop);
  EXPECT_EQ(f->records.back().body.at(0),
            static_cast<std::uint8_t>(rigdata::gfr::stop_reason::signal));
  // The device answered the STOP with a STATUS that says idle.
  std::optional<p::status_msg> last;
  for (const auto& r : f->records) {
    if (r.type != rigdata::gfr::kind::frame ||
        r.body[0] != static_cast<std::uint8_t>(p::msg::status))
      continue;
    const p::frame fr{r.body[0], 0, r.body.data() + 3, r.body.size() - 3};
    p::status_msg s;
    ASSERT_TRUE(fr.as(s));
    last = s;
  }
  ASSERT_TRUE(last);
  EXPECT_EQ(last->state, static_cast<std::uint8_t>(p::device_state::idle));
  auto run = rigdata::read_rig_run(gfr);
  ASSERT_TRUE(run);
  EXPECT_GT(run->dwells.size(), 20u);  // 1.5 s at 50x
}

// SIGKILL at 20 random moments: every file reads back, and every DWELL the emulator logged as
// sent more than 1 s before the kill is in it.
TEST(RecordCli, SigkillAtRandomMomentsLosesNothingSentBeforeIt) {
  test::temp_dir dir;
  const std::string log = dir.path() + "/sent.csv";
  emulator_process emu(dir.path(), "--speed 100 --seed 11 --log " + log);
  std::mt19937 rng(20261123);
  std::uniform_int_distribution<int> wait_ms(200, 900);
  for (int k = 0; k < 20; ++k) {
    SCOPED_TRACE(k);
    const std::string gfr = dir.path() + "/run" + std::to_string(k) + ".gfr";
    const std::size_t before = read_log(log).size();
    const int pid = test::spawn_cli({"record", "--port", emu.pty(), "-o", gfr});
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms(rng)));
    // Sent by now, in this recorder's run: the rows after the first cycle-0 A dwell it started.
    const auto sent = [&] {
      const auto rows = read_log(log);
      std::set<long long> out;
      bool in_run = false;
      for (std::size_t i = before; i < rows.size(); ++i) {
        in_run = in_run || (rows[i].at(1) == 0 && rows[i].at(2) == 0);
        if (in_run) out.insert(rows[i].at(3));  // t_start_ticks
      }
      return out;
    };
    // A loaded machine (the sanitizer suite on a fresh CI machine) may start the recorder late:
    // wait for a few dwells of this run before the kill, so that the check below is never empty.
    auto must = sent();
    for (int w = 0; w < 600 && must.size() <= 5; ++w) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      must = sent();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    kill(pid, SIGKILL);
    EXPECT_EQ(test::wait_cli(pid), 128 + SIGKILL);
    auto run = rigdata::read_rig_run(gfr);
    ASSERT_TRUE(run) << run.err().message;
    std::set<long long> have;
    for (const auto& d : run->dwells) have.insert(d.d.t_start_ticks);
    EXPECT_GT(must.size(), 5u);
    for (const long long t : must) EXPECT_EQ(have.count(t), 1u) << "DWELL at tick " << t;
  }
}

TEST(RecordCli, ADamagedFileSaysWhereAndReadsWhatIsIntact) {
  test::temp_dir dir;
  const std::string good = dir.path() + "/good.gfr";
  {
    emulator_process emu(dir.path(), "--speed max --seed 2");
    ASSERT_EQ(run_cli({"record", "--port", emu.pty(), "--duration", "300", "-o", good}).exit_code,
              0);
  }
  const std::string whole = test::read_text(good);
  ASSERT_GT(whole.size(), 400u);
  struct damage {
    std::string name, bytes, says;
  };
  std::string future = whole;
  future[8] = 9;  // version 9, with its header checksum: a newer gyroflip's file
  const std::uint32_t crc = rigdata::gfr::crc32(
      std::span(reinterpret_cast<const std::uint8_t*>(future.data()), std::size_t{12}));
  for (std::size_t k = 0; k < 4; ++k) future[12 + k] = static_cast<char>(crc >> (8 * k));
  const std::vector<damage> cases = {
      {"truncated", whole.substr(0, 11), "record 0: the file header is cut short"},
      {"not_a_recording", "time_s,angle_deg,rate_dps\n0,0,1\n",
       "record 0: not a gyroflip rig recording"},
      {"future", future, "record 0: format version 9 is newer"},
      {"joined", whole + whole, "two .gfr files were joined"},
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
  // A damaged file header (issue 32): one flipped bit is repaired, more is read past; both named.
  std::string flipped_header = whole, magic = whole;
  flipped_header[9] = static_cast<char>(flipped_header[9] ^ 0x10);
  magic[0] = 'G';
  for (const auto& [name, bytes, says] :
       std::vector<damage>{{"flipped_header", flipped_header, "record 0: one flipped bit"},
                           {"magic", magic, "record 0: the file header is damaged"}}) {
    const std::string path = dir.path() + "/" + name + ".gfr";
    test::write_text(path, bytes);
    const auto r = run_cli({"export", path, "-o", dir.path() + "/" + name + ".csv"});
    EXPECT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << name << ": " << r.err;
  }
  // Bits flipped in the middle: one is repaired, two in one record are a damaged region skipped
  // up to the next intact record; every intact record reads, with a warning naming the damage;
  // --strict refuses. adev and noise show the warning too.
  // The bit is in a STATUS frame's record (a damaged DWELL would leave a gap in the series,
  // which adev refuses: that is the gap test's).
  std::size_t flip_at = std::string::npos;
  {
    auto f = rigdata::gfr::read(good);
    ASSERT_TRUE(f) << f.err().message;
    for (std::size_t i = f->records.size() / 2; i < f->records.size(); ++i) {
      const auto& b = f->records[i].body;
      if (f->records[i].type != rigdata::gfr::kind::frame ||
          b.at(0) != static_cast<std::uint8_t>(p::msg::status))
        continue;
      flip_at = whole.find(std::string(b.begin(), b.end()));
      if (flip_at != std::string::npos) flip_at += b.size() / 2;
      break;
    }
  }
  ASSERT_NE(flip_at, std::string::npos);
  for (const int bits : {1, 2}) {
    std::string flipped_body = whole;
    for (int b = 0; b < bits; ++b)
      flipped_body[flip_at + static_cast<std::size_t>(b)] =
          static_cast<char>(flipped_body[flip_at + static_cast<std::size_t>(b)] ^ 0x01);
    const std::string fb = dir.path() + "/flipped_body.gfr";
    test::write_text(fb, flipped_body);
    const char* says = bits == 1 ? "flipped bit" : "damaged bytes";
    for (const auto& cmd : {std::vector<std::string>{"export", fb, "-o", dir.path() + "/fb.csv"},
                            std::vector<std::string>{"adev", fb, "-o", dir.path() + "/fb_adev.csv"},
                            std::vector<std::string>{"noise", fb}}) {
      const auto r = run_cli(cmd);
      EXPECT_EQ(r.exit_code, 0) << cmd[0] << ": " << r.err;
      EXPECT_NE(r.err.find(says), std::string::npos) << cmd[0] << ": " << r.err;
    }
    const auto strict = run_cli({"export", fb, "--strict", "-o", dir.path() + "/fs.csv"});
    EXPECT_EQ(strict.exit_code, 2) << strict.err;
    EXPECT_FALSE(test::exists(dir.path() + "/fs.csv"));
    std::remove(fb.c_str());
  }
  // Zeros at the end (a power loss) and a torn last record (a killed recorder): read, warned.
  for (const std::string& tail :
       {whole + std::string(8, '\0'), whole.substr(0, whole.size() - 3)}) {
    const std::string t = dir.path() + "/tail.gfr";
    test::write_text(t, tail);
    const auto r = run_cli({"export", t, "-o", dir.path() + "/tail.csv"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.err.find("zeros") != std::string::npos ||
                r.err.find("cut off while it was written") != std::string::npos)
        << r.err;
    std::remove(t.c_str());
  }
  // A folder named like a recording.
  const std::string folder = dir.path() + "/folder.gfr";
  ASSERT_EQ(::mkdir(folder.c_str(), 0755), 0);
  const auto fr = run_cli({"export", folder, "-o", dir.path() + "/folder.csv"});
  EXPECT_EQ(fr.exit_code, 2) << fr.err;
  EXPECT_NE(fr.err.find("is a directory"), std::string::npos) << fr.err;
}

}  // namespace
