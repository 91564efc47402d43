// Real logger files into `adev` and `noise` (issue 12): units, epoch time stamps, gaps and
// jitter, delimiters and decimal commas, files without a header, and Kalibr's noise file. Each
// test writes a small file the way a logger writes it and compares with the same data written
// the way gyroflip writes it.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <hdf5.h>

#include <nlohmann/json.hpp>

#include "gyroflip/core/version.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

using nlohmann::json;
constexpr double deg_per_rad = 180.0 / std::numbers::pi;

// 100 Hz rate samples (deg/s): white noise N = 0.01 deg/s/sqrt(Hz) plus a rate random walk
// K = 0.002 deg/s/sqrt(s), three axes from one seeded generator.
std::vector<std::vector<double>> three_axes(std::size_t n) {
  std::mt19937_64 rng(20261123);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::vector<double>> axes(3, std::vector<double>(n));
  for (auto& a : axes) {
    double walk = 0.0;
    for (auto& x : a) {
      walk += 0.002 * std::sqrt(0.01) * g(rng);
      x = 0.01 * std::sqrt(100.0) * g(rng) + walk;
    }
  }
  return axes;
}

// gyroflip's own form: time_s,gx,gy,gz with '.' decimals.
std::string plain_csv(const std::vector<std::vector<double>>& a, double scale) {
  std::string s = "time_s,gx,gy,gz\n";
  for (std::size_t k = 0; k < a[0].size(); ++k)
    s += fmt::format("{},{:.17g},{:.17g},{:.17g}\n", 0.01 * static_cast<double>(k), a[0][k] * scale,
                     a[1][k] * scale, a[2][k] * scale);
  return s;
}

json run_json(const std::vector<std::string>& args) {
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code != 0) return json::object();
  return json::parse(r.out);
}

std::vector<double> devs(const json& j) {
  std::vector<double> d;
  for (const auto& p : j["points"]) d.push_back(p["dev"].get<double>());
  return d;
}

TEST(CliLoggers, NanosecondEpochStampsInRadiansGiveTheSameCurveTimesTheFactor) {
  temp_dir dir;
  const auto a = three_axes(20000);
  write_text(dir.file("plain.csv"), plain_csv(a, 1.0));
  // A ROS-style log: epoch stamps in ns (1.7e18: beyond a double's integer precision), rad/s.
  std::string ros = "stamp_ns,wx,wy,wz\n";
  const std::int64_t t0 = 1'700'000'000'123'456'789;
  for (std::size_t k = 0; k < a[0].size(); ++k)
    ros +=
        fmt::format("{},{:.17g},{:.17g},{:.17g}\n", t0 + static_cast<std::int64_t>(k) * 10'000'000,
                    a[0][k] / deg_per_rad, a[1][k] / deg_per_rad, a[2][k] / deg_per_rad);
  write_text(dir.file("ros.csv"), ros);
  const json plain = run_json({"adev", dir.file("plain.csv"), "--column", "gy", "--json"});
  const json rad = run_json({"adev", dir.file("ros.csv"), "--column", "wy", "--time-column",
                             "stamp_ns", "--time-unit", "ns", "--units", "rad/s", "--json"});
  EXPECT_DOUBLE_EQ(rad["tau0_s"].get<double>(), 0.01);
  EXPECT_EQ(rad["units"], "rad/s");
  EXPECT_EQ(plain["units"], "deg/s");
  EXPECT_EQ(rad["column"], "wy");
  const auto d_deg = devs(plain), d_rad = devs(rad);
  ASSERT_EQ(d_deg.size(), d_rad.size());
  ASSERT_GT(d_deg.size(), 8u);
  for (std::size_t i = 0; i < d_deg.size(); ++i)
    EXPECT_NEAR(d_rad[i] * deg_per_rad / d_deg[i], 1.0, 1e-9) << i;

  // noise: the same terms in deg units whatever the input's unit, and the rad ones by the factor.
  const json n_deg = run_json({"noise", dir.file("plain.csv"), "--column", "gy", "--json"});
  const json n_rad = run_json({"noise", dir.file("ros.csv"), "--column", "wy", "--time-column",
                               "stamp_ns", "--time-unit", "ns", "--units", "rad/s", "--json"});
  for (std::string key : {"arw_dps_rthz", "arw_deg_rth", "rrw_deg_h_rth", "bias_floor_deg_h"}) {
    if (n_deg[key].is_null()) key += "_upper";  // not resolved in 200 s: its upper limit
    ASSERT_TRUE(n_deg[key].is_number()) << key;
    EXPECT_NEAR(n_rad[key].get<double>() / n_deg[key].get<double>(), 1.0, 1e-9) << key;
  }
  EXPECT_NEAR(n_rad["arw_rad_s_rthz"].get<double>() * deg_per_rad,
              n_rad["arw_dps_rthz"].get<double>(), 1e-15);
  // The truth: N = 0.01 deg/s/sqrt(Hz) within its interval widened to 3 sigma.
  const double arw = n_deg["arw_dps_rthz"], lo = n_deg["arw_dps_rthz_lo"],
               hi = n_deg["arw_dps_rthz_hi"];
  EXPECT_NEAR(arw, 0.01, 3 * (hi - lo) / 2);
}

// Issue 21: stamps past int64 (9.2e18) fell back to doubles and were reported as "does not
// increase". Integer ns stamps crossing 2^63 - 1, and 22-digit ns stamps (past 2^64), at 10 ms
// steps give the curve of the same samples stamped in seconds; 39 digits are refused by name.
TEST(CliLoggers, StampsPastInt64AreRebasedExactly) {
  temp_dir dir;
  const auto a = three_axes(3000);
  write_text(dir.file("plain.csv"), plain_csv(a, 1.0));
  const json want = run_json({"adev", dir.file("plain.csv"), "--column", "gx", "--json"});
  const auto stamped = [&](const std::string& name, auto stamp) {
    std::string csv = "t,gx\n";
    for (std::size_t k = 0; k < a[0].size(); ++k)
      csv += stamp(static_cast<unsigned long long>(k)) + fmt::format(",{:.17g}\n", a[0][k]);
    write_text(dir.file(name), csv);
    return run_json({"adev", dir.file(name), "--column", "gx", "--time-column", "t", "--time-unit",
                     "ns", "--json"});
  };
  for (const json& j :
       {stamped("cross.csv",
                [](unsigned long long k) {
                  return fmt::format("{}", 9223372036854775000ULL + k * 10'000'000ULL);
                }),
        stamped("wide.csv", [](unsigned long long k) {
          return fmt::format("17000000001{:011}", 23456789000ULL + k * 10'000'000ULL);
        })}) {
    EXPECT_DOUBLE_EQ(j["tau0_s"].get<double>(), 0.01);
    EXPECT_EQ(devs(j), devs(want));
  }
  write_text(dir.file("long.csv"), "t,gx\n" + std::string(39, '1') + ",1\n" + std::string(38, '1') +
                                       "2,2\n" + std::string(38, '1') + "3,3\n");
  const auto r = run_cli({"adev", dir.file("long.csv"), "--column", "gx", "--time-column", "t"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("long.csv:2:1: time stamp " + std::string(39, '1') +
                       " has more than 38 digits before the decimal mark"),
            std::string::npos)
      << r.err;
}

TEST(CliLoggers, SemicolonsDecimalCommasNoHeaderThreeAxesReadAsThePlainFile) {
  temp_dir dir;
  const auto a = three_axes(3000);
  write_text(dir.file("plain.csv"), plain_csv(a, 1.0));
  // A European spreadsheet export: ';' between fields, ',' as the decimal mark, no header.
  std::string eu;
  for (std::size_t k = 0; k < a[0].size(); ++k) {
    std::string row = fmt::format("{:.2f};{:.17g};{:.17g};{:.17g}\n", 0.01 * static_cast<double>(k),
                                  a[0][k], a[1][k], a[2][k]);
    for (char& c : row)
      if (c == '.') c = ',';
    eu += row;
  }
  write_text(dir.file("eu.csv"), eu);
  // Blanks between fields (a MATLAB `save -ascii`), with a header.
  std::string blanks = "  t        gx   gy   gz\n";
  for (std::size_t k = 0; k < a[0].size(); ++k)
    blanks += fmt::format("  {:.2f}\t {:.17g}  {:.17g} {:.17g}\n", 0.01 * static_cast<double>(k),
                          a[0][k], a[1][k], a[2][k]);
  write_text(dir.file("blanks.txt"), blanks);
  // Tab-separated (a LabVIEW or Excel "text" export), detected; and the same given explicitly.
  std::string tabs = "time_s\tgx\tgy\tgz\n";
  for (std::size_t k = 0; k < a[0].size(); ++k)
    tabs += fmt::format("{:.2f}\t{:.17g}\t{:.17g}\t{:.17g}\n", 0.01 * static_cast<double>(k),
                        a[0][k], a[1][k], a[2][k]);
  write_text(dir.file("tabs.tsv"), tabs);
  for (const char* axis : {"gx", "gz"}) {
    SCOPED_TRACE(axis);
    const std::string number = axis[1] == 'x' ? "2" : "4";
    const auto want = devs(run_json({"adev", dir.file("plain.csv"), "--column", axis, "--json"}));
    const auto eu_devs = devs(run_json({"adev", dir.file("eu.csv"), "--no-header", "--decimal", ",",
                                        "--column", number, "--time-column", "1", "--json"}));
    const auto blank_devs = devs(run_json(
        {"adev", dir.file("blanks.txt"), "--column", axis, "--time-column", "t", "--json"}));
    const auto tab_devs =
        devs(run_json({"adev", dir.file("tabs.tsv"), "--column", axis, "--json"}));
    const auto tab_given = devs(
        run_json({"adev", dir.file("tabs.tsv"), "--column", axis, "--delimiter", "tab", "--json"}));
    ASSERT_EQ(eu_devs.size(), want.size());
    ASSERT_EQ(blank_devs.size(), want.size());
    ASSERT_EQ(tab_devs.size(), want.size());
    EXPECT_EQ(tab_given, tab_devs);
    for (std::size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(eu_devs[i], want[i]) << i;
      EXPECT_EQ(blank_devs[i], want[i]) << i;
      EXPECT_EQ(tab_devs[i], want[i]) << i;
    }
  }
  // A column that is not there: the message shows the header as split and the delimiter.
  const auto r = run_cli({"adev", dir.file("eu.csv"), "--decimal", ",", "--column", "gx"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("eu.csv:1:1: missing required column 'gx'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fields split at ';'"), std::string::npos) << r.err;
  // A '.' in a decimal-comma file is not guessed at.
  write_text(dir.file("mixed.csv"), "time_s;x\n0;1,5\n0,01;1.5\n0,02;2,5\n0,03;1\n");
  const auto m = run_cli({"adev", dir.file("mixed.csv"), "--decimal", ",", "--column", "x"});
  EXPECT_EQ(m.exit_code, 2);
  EXPECT_NE(m.err.find("mixed.csv:3:6: '1.5' has a '.' while the decimal mark is ','"),
            std::string::npos)
      << m.err;
}

// 100 Hz stamps with a 10-ms gap at 25 s (one sample missing): the error names the line after the
// gap and the time before it; --gaps split analyses the longer run and says so.
TEST(CliLoggers, AGapIsNamedWhereItIsAndSplitAnalysesTheLongestRun) {
  temp_dir dir;
  const auto a = three_axes(6000);
  std::string s = "time_s,gx\n";
  std::size_t line = 1, gap_line = 0;
  for (std::size_t k = 0; k < a[0].size(); ++k) {
    if (k == 2500) continue;  // the sample at 25.00 s is missing
    ++line;
    if (k == 2501) gap_line = line;
    s += fmt::format("{:.2f},{:.17g}\n", 0.01 * static_cast<double>(k), a[0][k]);
  }
  write_text(dir.file("gap.csv"), s);
  const auto r = run_cli({"adev", dir.file("gap.csv"), "--column", "gx"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(fmt::format("gap.csv:{}:1: the time stamps have 1 gap", gap_line)),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("after sample 2500 (time 24.99 s) the next comes 0.02 s later, about 1 "
                       "sample missing"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--gaps split"), std::string::npos) << r.err;
  const auto split =
      run_cli({"adev", dir.file("gap.csv"), "--column", "gx", "--gaps", "split", "--json"});
  ASSERT_EQ(split.exit_code, 0) << split.err;
  EXPECT_NE(split.err.find("analysed: samples 2501 to 5999 (time 25.01 to 59.99 s), the longest "
                           "of 2 gap-free runs"),
            std::string::npos)
      << split.err;
  EXPECT_EQ(json::parse(split.out)["samples"], 3499);
}

TEST(CliLoggers, JitterIsAcceptedAndReportedAndARateThatDisagreesIsAnError) {
  temp_dir dir;
  const auto a = three_axes(4000);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.002, 0.002);  // +-20 % of 10 ms
  std::string s = "time_s,gx\n";
  for (std::size_t k = 0; k < a[0].size(); ++k)
    s += fmt::format("{:.6f},{:.17g}\n", 0.01 * static_cast<double>(k) + jitter(rng), a[0][k]);
  write_text(dir.file("jitter.csv"), s);
  const auto r = run_cli({"adev", dir.file("jitter.csv"), "--column", "gx", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("note:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the time stamps jitter by up to"), std::string::npos) << r.err;
  EXPECT_NEAR(json::parse(r.out)["tau0_s"].get<double>(), 0.01, 1e-6);
  // --rate within 1 % of the stamps' rate is taken as exact; beyond, an error with both.
  const auto ok =
      run_cli({"adev", dir.file("jitter.csv"), "--column", "gx", "--rate", "100.5", "--json"});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_DOUBLE_EQ(json::parse(ok.out)["tau0_s"].get<double>(), 1.0 / 100.5);
  const auto bad = run_cli({"adev", dir.file("jitter.csv"), "--column", "gx", "--rate", "200"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("the sample rate 200 Hz disagrees with the time stamps' 99.99"),
            std::string::npos)
      << bad.err;
  EXPECT_NE(bad.err.find("(option --rate)"), std::string::npos) << bad.err;
}

// Every axis at once, as MATLAB's allanvar takes an N x M matrix: one pass over the file, each
// column's result equal to its own run, named in CSV (a column field), JSON and text.
TEST(CliLoggers, SeveralColumnsInOneRunGiveEachColumnsOwnResult) {
  temp_dir dir;
  write_text(dir.file("imu.csv"), plain_csv(three_axes(5000), 1.0));
  const json all = run_json({"adev", dir.file("imu.csv"), "--columns", "all-numeric", "--json"});
  const json named = run_json({"adev", dir.file("imu.csv"), "--column", "gx,gy,gz", "--json"});
  ASSERT_EQ(all["columns"].size(), 3u);
  EXPECT_EQ(all, named);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string axis = std::string("g") + "xyz"[i];
    const json one = run_json({"adev", dir.file("imu.csv"), "--column", axis, "--json"});
    EXPECT_EQ(all["columns"][i]["column"], axis);
    EXPECT_EQ(devs(all["columns"][i]), devs(one)) << axis;
  }
  const auto csv = run_cli({"adev", dir.file("imu.csv"), "--column", "gx,gz"});
  ASSERT_EQ(csv.exit_code, 0) << csv.err;
  EXPECT_EQ(csv.out.rfind("column,tau_s,dev,ci_lo,ci_hi,edf,n,alpha\n# units: deg/s\ngx,", 0), 0u)
      << csv.out;
  EXPECT_NE(csv.out.find("\ngz,"), std::string::npos);
  const json noise = run_json({"noise", dir.file("imu.csv"), "--columns", "all-numeric", "--json"});
  ASSERT_EQ(noise["columns"].size(), 3u);
  EXPECT_EQ(noise["columns"][2]["column"], "gz");
  const auto text = run_cli({"noise", dir.file("imu.csv"), "--column", "gx,gy"});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("column gx,"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("column gy,"), std::string::npos) << text.out;
  // A column that is not there names itself.
  const auto bad = run_cli({"adev", dir.file("imu.csv"), "--column", "gx,wy"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("missing required column 'wy'"), std::string::npos) << bad.err;
}

// The fit's range, the read-offs beside the fit, and the terms written to a file.
TEST(CliLoggers, NoiseFitRangeReadOffsAndTermsFile) {
  temp_dir dir;
  write_text(dir.file("imu.csv"), plain_csv(three_axes(60000), 1.0));
  const json all = run_json(
      {"noise", dir.file("imu.csv"), "--column", "gx", "--json", "-o", dir.file("terms.csv")});
  const json part = run_json({"noise", dir.file("imu.csv"), "--column", "gx", "--json",
                              "--fit-taus", "0.01:10", "-o", dir.file("terms.json")});
  EXPECT_LT(part["oadev"].size(), all["oadev"].size() + 1);  // the points shown stay all
  EXPECT_NE(part["arw_dps_rthz"], all["arw_dps_rthz"]);      // the fit saw fewer of them
  // N read at tau 1 s off the -1/2 slope: the truth 0.01 deg/s/sqrt(Hz) within 10 %.
  ASSERT_TRUE(all["readoffs"]["arw_dps_rthz"].is_number()) << all["readoffs"].dump();
  EXPECT_NEAR(all["readoffs"]["arw_dps_rthz"].get<double>(), 0.01, 0.001);
  EXPECT_EQ(json::parse(read_text(dir.file("terms.json"))), part);
  const std::string csv = read_text(dir.file("terms.csv"));
  EXPECT_EQ(csv.rfind("column,term,unit,value,lo,hi,resolved,read_off\ngx,arw,deg/sqrt(h),", 0), 0u)
      << csv;
  // A sinusoid (a temperature swing of 20-s period) is no IEEE 952 term: the fit is poor and
  // says so; the model-only white noise fits (no warning).
  std::string sine = "time_s,gx\n";
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0.0, 0.1);
  for (std::size_t k = 0; k < 60000; ++k) {
    const double t = 0.01 * static_cast<double>(k);
    sine +=
        fmt::format("{:.2f},{:.9f}\n", t, g(rng) + 0.05 * std::sin(2 * std::numbers::pi * t / 20));
  }
  write_text(dir.file("sine.csv"), sine);
  const auto poor = run_cli({"noise", dir.file("sine.csv"), "--column", "gx"});
  ASSERT_EQ(poor.exit_code, 0) << poor.err;
  EXPECT_NE(poor.err.find("the noise model fits the curve poorly (chi2/dof"), std::string::npos)
      << poor.err;
  EXPECT_EQ(run_cli({"noise", dir.file("imu.csv"), "--column", "gx"}).err.find("fits the curve"),
            std::string::npos);
  const auto bad = run_cli({"noise", dir.file("imu.csv"), "--column", "gx", "--fit-taus", "5"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--fit-taus: LO:HI"), std::string::npos) << bad.err;
}

// Kalibr's file: tests/cli/test_cli_imu.cpp (issue 34 item 3).

// Flip recordings as a rig with an encoder writes them: angles near 0 and 180, accepted within a
// stated tolerance; calibrate reads the table simulate writes; the rules are in --help;
// compensate's JSON says its layout version and the dN it subtracted.
TEST(CliLoggers, EncoderAnglesWithinATolerancePositionsAndTheCompensateSummary) {
  temp_dir dir;
  const std::string sim = dir.file("sim.csv"), enc = dir.file("enc.csv");
  ASSERT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "300", "--seed", "4",
                     "-o", sim})
                .exit_code,
            0);
  // The same rows with the encoder's readings: 0.3 (or 359.8) for 0, 179.7 / 180.2 for 180.
  std::string text = read_text(sim), out;
  std::size_t row = 0;
  for (std::size_t at = 0; at < text.size();) {
    const auto nl = text.find('\n', at);
    std::string line = text.substr(at, nl - at);
    at = nl + 1;
    if (line.empty() || line[0] == '#' || line.rfind("time_s", 0) == 0) {
      out += line + "\n";
      continue;
    }
    const auto c1 = line.find(','), c2 = line.find(',', c1 + 1);
    const std::string angle = line.substr(c1 + 1, c2 - c1 - 1);
    const char* reading = angle == "0"     ? (row % 2 ? "0.3" : "359.8")
                          : angle == "180" ? (row % 2 ? "179.7" : "180.2")
                                           : "";
    ++row;
    out += line.substr(0, c1 + 1) + reading + line.substr(c2) + "\n";
  }
  write_text(enc, out);
  const auto refused = run_cli({"calibrate", enc});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("deg is not supported: only 0 and 180"), std::string::npos)
      << refused.err;
  const json exact = run_json({"calibrate", sim, "--json"});
  const json read = run_json({"calibrate", enc, "--angle-tolerance", "0.5", "--json"});
  EXPECT_EQ(read["delta_n_dps"], exact["delta_n_dps"]);
  EXPECT_EQ(run_cli({"calibrate", enc, "--angle-tolerance", "0.25"}).exit_code, 2);
  EXPECT_EQ(run_cli({"calibrate", enc, "--angle-tolerance", "11"}).exit_code, 2);
  // simulate writes its table (`# positions_deg:`) and calibrate reads any table that holds the
  // pair (issue 33; before, only 0 and 180 within a tolerance): 0.5/180.5 without a tolerance,
  // and 90/270 (+1 at 90 deg, of the two the nearer 0). Positions are whole steps of the table
  // (rig_config): 0.5-deg steps here.
  const std::string off = dir.file("off.csv");
  ASSERT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "60", "--positions",
                     "0.5,180.5", "--steps-per-rev", "720", "-o", off})
                .exit_code,
            0);
  const auto between = run_cli({"simulate", "--sensor", "hz1-90-100a", "--positions", "0.5,180.5"});
  EXPECT_EQ(between.exit_code, 2);
  EXPECT_NE(between.err.find("not a whole number of the table's 1.8-deg steps"), std::string::npos)
      << between.err;
  EXPECT_NE(between.err.find("(option --positions)"), std::string::npos) << between.err;
  EXPECT_EQ(run_cli({"calibrate", off}).exit_code, 0);
  EXPECT_EQ(run_cli({"calibrate", off, "--angle-tolerance", "1"}).exit_code, 0);
  const std::string far = dir.file("far.csv");
  ASSERT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "60", "--positions",
                     "90,270", "-o", far})
                .exit_code,
            0);
  EXPECT_EQ(run_cli({"calibrate", far}).exit_code, 0);
  const auto help = run_cli({"calibrate", "--help"});
  EXPECT_NE(help.out.find("A dwell is a run of rows with equal angle_deg"), std::string::npos)
      << help.out;
  EXPECT_NE(help.out.find("dN = (r_0 - r_180) / 2"), std::string::npos);
  const json comp = run_json({"compensate", sim, "--delta-n", "0.0031", "--json"});
  EXPECT_EQ(comp["schema"], "gyroflip.compensate/2");  // io/schema.hpp: one convention
  EXPECT_EQ(comp["version"], std::string(gyroflip::version()));
  EXPECT_EQ(comp["delta_n"]["delta_n_dps"], 0.0031);
  EXPECT_EQ(comp["delta_n"]["degree"], 0);
  EXPECT_EQ(comp["delta_n"]["source"], "--delta-n");
}

// On a terminal `adev` prints a table a person reads (unit in the header, m, 4 digits); piped it
// prints the CSV with every digit. The terminal is script(1)'s pty.
TEST(CliLoggers, AdevPrintsATableOnATerminalAndCsvWhenPiped) {
  if (std::system("script --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "no script(1)";
  temp_dir dir;
  write_text(dir.file("r.csv"), plain_csv(three_axes(2000), 1.0 / deg_per_rad));
  const std::string cmd = std::string("script -qec '") + GYROFLIP_EXE + " adev " +
                          dir.file("r.csv") + " --column gx --units rad/s' /dev/null > " +
                          dir.file("tty.txt");
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const std::string tty = read_text(dir.file("tty.txt"));
  EXPECT_NE(tty.find("oadev of column gx, 2000 samples at 100 Hz, 68.3 % intervals"),
            std::string::npos)
      << tty;
  EXPECT_NE(tty.find("tau [s]         m   dev [rad/s]"), std::string::npos) << tty;
  EXPECT_NE(tty.find("       0.01         1 "), std::string::npos) << tty;
  const auto piped = run_cli({"adev", dir.file("r.csv"), "--column", "gx", "--units", "rad/s"});
  EXPECT_EQ(piped.out.rfind("tau_s,dev,ci_lo,ci_hi,edf,n,alpha\n# units: rad/s\n", 0), 0u)
      << piped.out;
}

// A .npy table as np.save writes it: `descr` and `shape` (N, M) in C or Fortran order.
void write_npy_table(const std::string& path, const std::vector<std::vector<double>>& cols, bool f4,
                     bool fortran) {
  const std::size_t n = cols[0].size(), m = cols.size();
  std::string header = std::string("{'descr': '") + (f4 ? "<f4" : "<f8") +
                       "', 'fortran_order': " + (fortran ? "True" : "False") + ", 'shape': (" +
                       std::to_string(n) + ", " + std::to_string(m) + "), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string bytes = std::string("\x93NUMPY\x01\x00", 8);
  bytes += static_cast<char>(header.size() & 0xFF);
  bytes += static_cast<char>(header.size() >> 8);
  bytes += header;
  for (std::size_t k = 0; k < n * m; ++k) {
    const std::size_t r = fortran ? k % n : k / m, c = fortran ? k / n : k % m;
    if (f4) {
      const auto x = static_cast<float>(cols[c][r]);
      bytes.append(reinterpret_cast<const char*>(&x), sizeof x);  // NOLINT: bytes of a float
    } else {
      bytes.append(reinterpret_cast<const char*>(&cols[c][r]), sizeof(double));  // NOLINT
    }
  }
  write_text(path, bytes);
}

// Binary tables: a 2-D .npy (float64 C order, float32 Fortran order) and a 2-D HDF5 dataset
// give, column by number, the curve of the same column of the CSV.
TEST(CliLoggers, TwoDimensionalNpyAndHdf5TablesByColumnNumber) {
  temp_dir dir;
  const auto a = three_axes(3000);
  write_text(dir.file("plain.csv"), plain_csv(a, 1.0));
  write_npy_table(dir.file("t8.npy"), a, false, false);
  write_npy_table(dir.file("t4.npy"), a, true, true);
  const auto want = devs(run_json({"adev", dir.file("plain.csv"), "--column", "gy", "--json"}));
  const auto c8 =
      devs(run_json({"adev", dir.file("t8.npy"), "--column", "2", "--rate", "100", "--json"}));
  ASSERT_EQ(c8.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(c8[i] / want[i], 1.0, 1e-9) << i;
  const auto c4 =
      devs(run_json({"adev", dir.file("t4.npy"), "--column", "2", "--rate", "100", "--json"}));
  ASSERT_EQ(c4.size(), want.size());
  // float32 keeps 24 bits: the curve agrees to its rounding.
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(c4[i] / want[i], 1.0, 1e-4) << i;
  const auto no_col = run_cli({"adev", dir.file("t8.npy"), "--rate", "100"});
  EXPECT_EQ(no_col.exit_code, 2);
  EXPECT_NE(no_col.err.find(".npy array has 3 columns: give a column number from 1 to 3"),
            std::string::npos)
      << no_col.err;
  // HDF5: /imu/gyro, 3000 x 3 float64.
  const std::string h5 = dir.file("imu.h5");
  {
    const hid_t f = H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t g = H5Gcreate2(f, "/imu", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t dims[2] = {a[0].size(), 3};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t d =
        H5Dcreate2(g, "gyro", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<double> rows;
    for (std::size_t r = 0; r < a[0].size(); ++r)
      for (std::size_t c = 0; c < 3; ++c) rows.push_back(a[c][r]);
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data());
    H5Dclose(d);
    H5Sclose(space);
    H5Gclose(g);
    H5Fclose(f);
  }
  const auto h =
      devs(run_json({"adev", h5 + ":/imu/gyro", "--column", "2", "--rate", "100", "--json"}));
  ASSERT_EQ(h.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(h[i] / want[i], 1.0, 1e-9) << i;
  const auto h_bad = run_cli({"adev", h5 + ":/imu/gyro", "--column", "4", "--rate", "100"});
  EXPECT_EQ(h_bad.exit_code, 2);
  EXPECT_NE(h_bad.err.find("has 3 columns: give a column number from 1 to 3"), std::string::npos)
      << h_bad.err;
}

// `-` reads a CSV from standard input (a pipe from a logger): the same curve as the file; a gap
// is located by its line in the input.
TEST(CliLoggers, StandardInputIsReadAsACsv) {
  temp_dir dir;
  const auto a = three_axes(3000);
  write_text(dir.file("imu.csv"), plain_csv(a, 1.0));
  const std::string exe = GYROFLIP_EXE;
  const std::string cmd = "cat " + dir.file("imu.csv") + " | " + exe +
                          " adev - --column gx,gz --json > " + dir.file("out.json") + " 2> " +
                          dir.file("err.txt");
  ASSERT_EQ(std::system(cmd.c_str()), 0) << read_text(dir.file("err.txt"));
  const json piped = json::parse(read_text(dir.file("out.json")));
  const json file = run_json({"adev", dir.file("imu.csv"), "--column", "gx,gz", "--json"});
  ASSERT_EQ(piped["columns"].size(), 2u);
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_EQ(devs(piped["columns"][i]), devs(file["columns"][i])) << i;
  // No header and decimal commas through the pipe: its first row is data (read again).
  write_text(dir.file("nh.csv"), "0;1,5\n1;2\n2;3,25\n3;4\n4;1\n5;2,5\n");
  const std::string nh = "cat " + dir.file("nh.csv") + " | " + exe +
                         " adev - --no-header --decimal , --column 2 --time-column 1 --json > " +
                         dir.file("nh.json");
  ASSERT_EQ(std::system(nh.c_str()), 0);
  const json nh_file = run_json({"adev", dir.file("nh.csv"), "--no-header", "--decimal", ",",
                                 "--column", "2", "--time-column", "1", "--json"});
  const json nh_pipe = json::parse(read_text(dir.file("nh.json")));
  EXPECT_EQ(nh_pipe["samples"], 6);
  EXPECT_EQ(devs(nh_pipe), devs(nh_file));
  // A gap after the 3rd sample: the 5th line of the input (header on line 1).
  write_text(dir.file("gap.csv"), "time_s,gx\n0,1\n1,2\n2,3\n4,4\n5,5\n6,6\n7,7\n");
  const std::string gap = "cat " + dir.file("gap.csv") + " | " + exe + " adev - --column gx 2> " +
                          dir.file("gap.txt") + " > /dev/null";
  EXPECT_NE(std::system(gap.c_str()), 0);
  EXPECT_NE(read_text(dir.file("gap.txt")).find("<stdin>:5: the time stamps have 1 gap"),
            std::string::npos)
      << read_text(dir.file("gap.txt"));
}

}  // namespace
}  // namespace gyroflip::test
