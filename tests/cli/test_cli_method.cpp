// `gyroflip calibrate` and `gyroflip compensate`: JSON contract, calibration files, dN(T), and
// every bad-input case of issue 2 (message FILE:LINE:COL, exit 2, no output file).
#include <cmath>
#include <cstdint>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gyroflip/earth/earth.hpp"
#include "support/run_cli.hpp"
#include "support/synth.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

using nlohmann::json;

std::string recording(double delta_n, double bias_slope, double temp_c = 20.0, double input = 0.0) {
  synth_spec s;
  s.delta_n_dps = [delta_n](double) { return delta_n; };
  s.bias_dps = [bias_slope](double t) { return 0.5 + bias_slope * t; };
  s.temp_c = temp_c;
  s.input_dps = input;
  return to_csv(synth_rows(s), !std::isnan(temp_c));
}

TEST(CliCalibrate, JsonContractAndSplit) {
  temp_dir d;
  write_text(d.file("cal.csv"), recording(0.0123, 1e-4));
  const auto r =
      run_cli({"calibrate", d.file("cal.csv"), "--json", "--latitude", "42.6", "--axis", "north"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = json::parse(r.out);
  for (const char* k : {"delta_n_dps", "std_dps", "stderr_dps", "stderr_correlated_dps", "cycles",
                        "pairing", "earth_rate_dps", "g_term_dps", "temp_c"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_NEAR(j["delta_n_dps"].get<double>(), 0.0123, 1e-15);  // abba: ramp cancelled
  EXPECT_EQ(j["pairing"], "abba");
  EXPECT_EQ(j["cycles"], 60);
  EXPECT_NEAR(j["temp_c"].get<double>(), 20.0, 1e-12);
  const double earth_dps = earth::earth_rate_component_dps(42.6, *earth::parse_axis("north"));
  EXPECT_NEAR(j["earth_rate_dps"].get<double>(), earth_dps, 1e-15);
  EXPECT_NEAR(j["g_term_dps"].get<double>(), 0.0123 - earth_dps, 1e-15);
  EXPECT_FALSE(j.contains("model"));

  const auto simple =
      json::parse(run_cli({"calibrate", d.file("cal.csv"), "--json", "--pairing", "simple"}).out);
  EXPECT_NEAR(simple["delta_n_dps"].get<double>(), 0.0123 - 1e-4 * 0.895 / 2, 1e-15);
  EXPECT_TRUE(simple["earth_rate_dps"].is_null());
  EXPECT_TRUE(simple["g_term_dps"].is_null());

  const auto human = run_cli({"calibrate", d.file("cal.csv")});
  EXPECT_EQ(human.exit_code, 0);
  // An error at rounding level (a noiseless run): its 15 decimals.
  EXPECT_NE(human.out.find("dN = 0.0123000"), std::string::npos) << human.out;
}

TEST(CliCalibrate, LatitudeWithoutAxisIsUsageError) {
  temp_dir d;
  write_text(d.file("cal.csv"), recording(0.0123, 0.0));
  EXPECT_EQ(run_cli({"calibrate", d.file("cal.csv"), "--latitude", "42.6"}).exit_code, 2);
  EXPECT_EQ(
      run_cli({"calibrate", d.file("cal.csv"), "--latitude", "142", "--axis", "up"}).exit_code, 2);
  EXPECT_EQ(run_cli({"calibrate", d.file("cal.csv"), "--pairing", "fancy"}).exit_code, 2);
}

TEST(CliCalibrate, ThreeTemperaturesGiveModelAndCompensateUsesIt) {
  temp_dir d;
  const auto truth = [](double t) { return 0.0123 - 2e-4 * (t - 20.0); };
  std::vector<std::string> args{"calibrate"};
  for (double t : {4.0, 20.0, 30.0}) {
    const auto f = d.file("cal" + std::to_string(static_cast<int>(t)) + ".csv");
    write_text(f, recording(truth(t), 5e-5, t));
    args.push_back(f);
  }
  args.insert(args.end(), {"--json", "-o", d.file("model.json")});
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = json::parse(r.out);
  ASSERT_TRUE(j.contains("model"));
  EXPECT_EQ(j["model"]["kind"], "poly");
  const double t_ref = j["model"]["t_ref_c"].get<double>();
  const auto c = j["model"]["coeffs_dps"].get<std::vector<double>>();
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0] + c[1] * (4.0 - t_ref), truth(4.0), 1e-15);
  EXPECT_NEAR(c[1], -2e-4, 1e-15);
  EXPECT_EQ(j["files"].size(), 3u);
  EXPECT_EQ(json::parse(read_text(d.file("model.json"))), j);  // -o writes the same object

  // A run at 10 degC with a true input of 0.25 deg/s: dN(10) must be removed, not dN(20).
  write_text(d.file("run.csv"), recording(truth(10.0), -3e-4, 10.0, 0.25));
  const auto k =
      run_cli({"compensate", d.file("run.csv"), "--calibration", d.file("model.json"), "--json"});
  ASSERT_EQ(k.exit_code, 0) << k.err;
  const auto kj = json::parse(k.out);
  EXPECT_NEAR(kj["mean_dps"].get<double>(), 0.25, 1e-14);
  for (const char* key : {"cycles", "mean_dps", "std_dps", "stderr_correlated_dps", "drift_dps"})
    EXPECT_TRUE(kj.contains(key)) << key;

  // Repeats at one temperature (paper Tab. 3) give a degree-0 model: the runs' weighted mean.
  write_text(d.file("cal20b.csv"), recording(truth(20.0) + 4e-4, 5e-5, 20.0));
  const auto same = run_cli({"calibrate", d.file("cal20.csv"), d.file("cal20b.csv"), "--json"});
  ASSERT_EQ(same.exit_code, 0) << same.err;
  const auto sm = json::parse(same.out)["model"];
  EXPECT_EQ(sm["degree"], 0);
  EXPECT_NEAR(sm["coeffs_dps"][0].get<double>(), truth(20.0) + 2e-4, 1e-15);
  EXPECT_NEAR(std::sqrt(sm["cov"][0].get<double>()), 2e-4, 1e-15);  // scatter of two runs / sqrt(2)
  EXPECT_EQ(
      run_cli({"calibrate", d.file("cal20.csv"), d.file("cal20.csv"), "--degree", "1"}).exit_code,
      2);

  // A model needs temperatures in the run to compensate.
  write_text(d.file("notemp.csv"), recording(truth(10.0), 0.0, std::nan("")));
  const auto nt =
      run_cli({"compensate", d.file("notemp.csv"), "--calibration", d.file("model.json")});
  EXPECT_EQ(nt.exit_code, 2);
  EXPECT_NE(nt.err.find("temp_c"), std::string::npos);
}

TEST(CliCompensate, CsvOutputAndStdout) {
  temp_dir d;
  write_text(d.file("run.csv"), recording(0.0123 + 0.25, -1e-4));
  const auto r =
      run_cli({"compensate", d.file("run.csv"), "--delta-n", "0.0123", "-o", d.file("out.csv")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_text(d.file("out.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "time_s,rate_dps,bias_dps,temp_c,delta_n_dps");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 61 + 5);  // header, 5 metadata lines, rows
  EXPECT_NE(csv.find("\n# pairing: abba\n"), std::string::npos);
  const auto so = run_cli({"compensate", d.file("run.csv"), "--delta-n", "0.0123"});
  EXPECT_EQ(so.exit_code, 0);
  EXPECT_EQ(so.out, csv);
  EXPECT_EQ(run_cli({"compensate", d.file("run.csv")}).exit_code, 2);  // needs a dN source
  EXPECT_EQ(run_cli({"compensate", d.file("run.csv"), "--delta-n", "1", "--calibration", "x.json"})
                .exit_code,
            2);
  const auto badcal =
      run_cli({"compensate", d.file("run.csv"), "--calibration", d.file("run.csv")});
  EXPECT_EQ(badcal.exit_code, 2);
  EXPECT_NE(badcal.err.find("run.csv"), std::string::npos);
}

// Third review of issue 31, M4: calibrate's per-run line printed "dN = 4.788442e-03 ... 1.983e-04"
// and compensate's summary "mean 4.999999e-01": a number beside its error takes the error's
// decimals (the error two significant digits), never more; --json keeps the full digits.
TEST(CliCalibrate, PerRunNumbersCarryTheDigitsTheirErrorsSupport) {
  temp_dir d;
  const auto sim = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "600", "--temp",
                            "20", "--seed", "31", "-o", d.file("r.csv")});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto decimals = [](const std::string& n) {
    const auto dot = n.find('.');
    return dot == std::string::npos ? 0 : static_cast<int>(n.size() - dot - 1);
  };
  const auto human =
      run_cli({"calibrate", d.file("r.csv"), "--latitude", "42.6", "--axis", "north"});
  ASSERT_EQ(human.exit_code, 0) << human.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(human.out, m,
                                std::regex(R"(\n  dN = (\S+) deg/s   std (\S+)   stderr (\S+) )"
                                           R"(\(naive\) (\S+) \(correlated\))")))
      << human.out;
  EXPECT_EQ(human.out.find("e-0"), std::string::npos) << human.out;
  const std::string u = m[4];
  ASSERT_EQ(u.find_first_not_of("0."), u.size() - 2) << u;  // two significant digits
  EXPECT_EQ(decimals(m[1]), decimals(u)) << human.out;
  ASSERT_TRUE(std::regex_search(human.out, m, std::regex(R"(g term (\S+) deg/s)"))) << human.out;
  EXPECT_EQ(decimals(m[1]), decimals(u)) << human.out;
  const auto j = json::parse(run_cli({"calibrate", d.file("r.csv"), "--json"}).out);
  const double dn = j["delta_n_dps"].get<double>();

  const auto comp = run_cli(
      {"compensate", d.file("r.csv"), "--delta-n", std::to_string(dn), "-o", d.file("out.csv")});
  ASSERT_EQ(comp.exit_code, 0) << comp.err;
  ASSERT_TRUE(std::regex_search(
      comp.out, m, std::regex(R"(cycles, mean (\S+) deg/s, std (\S+), stderr (\S+) )")))
      << comp.out;
  const std::string cu = m[3];
  EXPECT_EQ(cu.find("e-"), std::string::npos) << comp.out;
  EXPECT_EQ(decimals(m[1]), decimals(cu)) << comp.out;
}

// Regression (issue 13 item 1): epoch-nanosecond stamps or a 1e-300-s window overran the drift
// window's arrays (ASan) and printed `drift -nan` with exit 0. Now: drift is "n/a" / null.
TEST(CliCompensate, DriftWindowBelowTimeResolutionIsNotANumber) {
  temp_dir d;
  std::string rows = "time_s,angle_deg,rate_dps\n";
  for (int k = 0; k < 6; ++k) rows += std::string("1.7e18,") + (k % 2 == 0 ? "0" : "180") + ",1\n";
  write_text(d.file("ns.csv"), rows);
  const auto r = run_cli({"compensate", d.file("ns.csv"), "--delta-n", "0", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(json::parse(r.out)["drift_dps"].is_null()) << r.out;
  write_text(d.file("run.csv"), recording(0.0123, 0.0));
  const auto w = run_cli(
      {"compensate", d.file("run.csv"), "--delta-n", "0", "--drift-window", "1e-300", "--json"});
  ASSERT_EQ(w.exit_code, 0) << w.err;
  EXPECT_TRUE(json::parse(w.out)["drift_dps"].is_null()) << w.out;
  EXPECT_EQ(w.out.find("nan"), std::string::npos);
}

// Issue 13 ("a user's first hour"): compensate applied any calibration silently. The calibration
// now records its sensor and rig (from the recordings' metadata); compensate refuses another
// sensor, warns on another rig setting, on a single-temperature dN far from its temperature,
// and on a calibration file that names no sensor.
TEST(CliCompensate, CalibrationBelongsToItsSensor) {
  temp_dir d;
  const auto sim = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> a{"simulate", "--duration", "300", "-o", d.file(out)};
    a.insert(a.end(), extra.begin(), extra.end());
    ASSERT_EQ(run_cli(a).exit_code, 0) << out;
  };
  sim("hz_cal.csv", {"--sensor", "hz1-90-100a", "--temp", "20"});
  sim("hz_run.csv", {"--sensor", "hz1-90-100a", "--temp", "20", "--seed", "2"});
  sim("hz_cold.csv", {"--sensor", "hz1-90-100a", "--temp", "4", "--seed", "3"});
  sim("hz_128.csv", {"--sensor", "hz1-90-100a", "--temp", "20", "--seed", "4", "--n-avg", "128"});
  sim("adx_run.csv", {"--sensor", "adxrs150", "--seed", "5"});
  const auto cal = d.file("cal.json");
  ASSERT_EQ(run_cli({"calibrate", d.file("hz_cal.csv"), "-o", cal}).exit_code, 0);
  const auto j = json::parse(read_text(cal));
  EXPECT_EQ(j["sensor"], "hz1-90-100a");
  EXPECT_EQ(j["rig"]["n_avg"], "256");
  // Same sensor, rig and temperature: silent.
  const auto same =
      run_cli({"compensate", d.file("hz_run.csv"), "--calibration", cal, "-o", d.file("o1.csv")});
  EXPECT_EQ(same.exit_code, 0);
  EXPECT_EQ(same.err, "");
  // Another sensor: refused.
  const auto other =
      run_cli({"compensate", d.file("adx_run.csv"), "--calibration", cal, "-o", d.file("o2.csv")});
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.err.find("recorded with sensor 'adxrs150'"), std::string::npos) << other.err;
  EXPECT_FALSE(exists(d.file("o2.csv")));
  // Another rig setting: warned.
  const auto rig =
      run_cli({"compensate", d.file("hz_128.csv"), "--calibration", cal, "-o", d.file("o3.csv")});
  EXPECT_EQ(rig.exit_code, 0);
  EXPECT_NE(rig.err.find("rig setting differs from the calibration's: n_avg 256 vs 128"),
            std::string::npos)
      << rig.err;
  // 16 degC from a single-temperature calibration: warned.
  const auto cold =
      run_cli({"compensate", d.file("hz_cold.csv"), "--calibration", cal, "-o", d.file("o4.csv")});
  EXPECT_EQ(cold.exit_code, 0);
  EXPECT_NE(cold.err.find("mean temperature 4.0 degC, but the calibration was made at 20.0 degC"),
            std::string::npos)
      << cold.err;
  // A calibration file from before (no sensor record): warned, still applied.
  write_text(d.file("old.json"), R"({"delta_n_dps": 0.003, "pairing": "abba"})");
  const auto old = run_cli({"compensate", d.file("hz_run.csv"), "--calibration", d.file("old.json"),
                            "-o", d.file("o5.csv")});
  EXPECT_EQ(old.exit_code, 0);
  EXPECT_NE(old.err.find("names no sensor"), std::string::npos) << old.err;
  // Two sensors in one calibration: refused.
  const auto mixed = run_cli({"calibrate", d.file("hz_cal.csv"), d.file("adx_run.csv")});
  EXPECT_EQ(mixed.exit_code, 2);
  EXPECT_NE(mixed.err.find("calibrate one sensor at a time"), std::string::npos) << mixed.err;
}

// --- bad input ---------------------------------------------------------------------------

std::vector<std::string> good_rows(int n = 40) {
  std::vector<std::string> rows;
  for (int k = 0; k < n; ++k)
    rows.push_back(std::to_string(k * 0.9) + "," + (k % 2 == 0 ? "0" : "180") + "," +
                   (k % 2 == 0 ? "0.21" : "0.19") + ",20.0,256\n");
  return rows;
}

std::string join(const std::vector<std::string>& rows) {
  std::string s = "time_s,angle_deg,rate_dps,temp_c,n_avg\n";
  for (const auto& r : rows) s += r;
  return s;
}

struct bad_case {
  std::string name;
  std::string text;
  std::string where;  // substring after the file name that the message must contain
};

std::vector<bad_case> bad_cases() {
  std::vector<bad_case> c;
  const auto with = [](std::size_t i, const std::string& row) {
    auto g = good_rows();
    g[i] = row;
    return join(g);
  };
  c.push_back({"empty.csv", "", ": empty file"});
  c.push_back({"header_only.csv", join({}), ": no data rows"});
  c.push_back({"no_rate.csv", "time_s,angle_deg,temp_c\n1,0,20\n",
               ":1:1: missing required column 'rate_dps'"});
  c.push_back({"dup.csv", "time_s,angle_deg,rate_dps,rate_dps\n1,0,2,3\n",
               ":1:27: duplicated column 'rate_dps'"});
  c.push_back(
      {"non_numeric.csv", with(3, "2.700,180,abc,20.0,256\n"), ":5:11: 'abc' is not a number"});
  c.push_back(
      {"nan.csv", with(5, "4.500,180,nan,20.0,256\n"), ":7:11: 'nan' is not a finite number"});
  c.push_back(
      {"inf.csv", with(4, "3.600,180,inf,20.0,256\n"), ":6:11: 'inf' is not a finite number"});
  c.push_back({"backwards.csv", with(7, "1.000,180,0.19,20.0,256\n"), ":9:1: time goes backwards"});
  c.push_back({"short.csv", with(10, "9.000,0\n"), ":12:8: row has 2 fields"});
  c.push_back(
      {"odd_angle.csv", with(2, "1.800,45,0.2,20.0,256\n"), ":4:7: angle 45 deg is not supported"});
  c.push_back({"bad_navg.csv", with(2, "1.800,0,0.2,20.0,2.5\n"),
               ":4:18: n_avg 2.5 is not a whole number"});
  auto one = good_rows();
  for (auto& r : one)
    r.replace(r.find(",180,") == std::string::npos ? 0 : r.find(",180,"),
              r.find(",180,") == std::string::npos ? 0 : 5,
              r.find(",180,") == std::string::npos ? "" : ",0,");
  c.push_back(
      {"one_orientation.csv", join(one), ": the table never turns (every row is at 0 deg)"});
  c.push_back(
      {"too_few.csv", join({good_rows()[0], good_rows()[1]}), ": only 0 cycles (2 dwells)"});
  std::string junk;
  for (int k = 0; k < 64; ++k)
    for (int i = 1; i < 256; ++i) junk.push_back(static_cast<char>(i == 10 ? 0 : i));
  c.push_back({"junk.bin", junk, ": binary data"});
  c.push_back({"huge.csv", join({}) + std::string(std::size_t{2} << 20, '1'),
               ":2: line longer than 1 MiB"});
  return c;
}

TEST(CliBadInput, EveryCaseNamesFileAndLineExitsTwoAndWritesNothing) {
  temp_dir d;
  for (const auto& c : bad_cases()) {
    SCOPED_TRACE(c.name);
    const auto path = d.file(c.name);
    write_text(path, c.text);
    const auto out = d.file("out.csv");
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"calibrate", path, "--json"},
             {"calibrate", path, "-o", out},
             {"compensate", path, "--delta-n", "0.001", "-o", out}}) {
      const auto r = run_cli(args);
      EXPECT_EQ(r.exit_code, 2) << args[0];
      EXPECT_NE(r.err.find(c.name + c.where), std::string::npos) << args[0] << ": " << r.err;
      EXPECT_TRUE(r.out.empty()) << args[0];
      EXPECT_FALSE(exists(out)) << args[0];
    }
  }
}

TEST(CliBadInput, MissingFileAndDirectory) {
  temp_dir d;
  for (const auto& path : {d.file("does-not-exist.csv"), d.path()}) {
    const auto r = run_cli({"compensate", path, "--delta-n", "0", "-o", d.file("o.csv")});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find(path + ": "), std::string::npos) << r.err;
    EXPECT_FALSE(exists(d.file("o.csv")));
  }
}

TEST(CliBadInput, BomAndCrlfAreAccepted) {
  temp_dir d;
  std::string text = "\xEF\xBB\xBF" + join(good_rows());
  std::string crlf;
  for (char ch : text) {
    if (ch == '\n') crlf += '\r';
    crlf += ch;
  }
  write_text(d.file("bom.csv"), crlf);
  const auto r = run_cli({"calibrate", d.file("bom.csv"), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(json::parse(r.out)["delta_n_dps"].get<double>(), 0.01, 1e-12);
}

}  // namespace
}  // namespace gyroflip::test

namespace gyroflip::test {
namespace {

// The true c1 of a simulated run from its truth file's header (Earth + g-term, first harmonic).
double truth_c1(const std::string& truth_file) {
  const std::string text = read_text(truth_file);
  const auto at = text.find("harmonics r(theta)");
  EXPECT_NE(at, std::string::npos);
  const auto line = text.substr(at, text.find('\n', at) - at);
  double e = 0.0, g = 0.0;
  const auto ec = line.find("earth c1 ");
  const auto gc = line.find("g_term c1 ");
  e = std::stod(line.substr(ec + 9));
  g = std::stod(line.substr(gc + 10));
  return e + g;
}

}  // namespace

// Issue 33 item 2: `calibrate --pairing harmonic` on a five-position run writes b and both
// harmonics with their covariance and the separability report (text and JSON), its c1 within 4
// of its own sigma of the truth (fixed seed), and `--explain` says before a run what a table
// cannot separate.
TEST(CliCalibrate, HarmonicTermsWithTheirCovarianceAndSeparability) {
  temp_dir d;
  const auto sim = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "900", "--seed",
                            "5", "--positions", "0,72,144,216,288", "--latitude", "42.6", "--axis",
                            "north", "-o", d.file("r5.csv"), "--truth", d.file("t5.csv")});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto r = run_cli({"calibrate", d.file("r5.csv"), "--pairing", "harmonic", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = json::parse(r.out);
  EXPECT_EQ(j["pairing"], "harmonic");
  std::vector<std::string> names;
  for (const auto& t : j["terms"]) names.push_back(t["name"].get<std::string>());
  EXPECT_EQ(names, (std::vector<std::string>{"b", "c1", "s1", "c2", "s2"}));
  ASSERT_EQ(j["terms_covariance"].size(), 5U);
  ASSERT_EQ(j["terms_covariance"][1].size(), 5U);
  const double c1 = j["terms"][1]["value_dps"].get<double>();
  const double se = j["terms"][1]["stderr_correlated_dps"].get<double>();
  EXPECT_NEAR(se * se, j["terms_covariance"][1][1].get<double>(), 1e-18);
  EXPECT_NEAR(c1, truth_c1(d.file("t5.csv")), 4.0 * se);
  bool earth_g = false;
  for (const auto& p : j["separability"]["inseparable"])
    earth_g |= p["first"] == "Earth rate" && p["second"] == "g-sensitivity";
  EXPECT_TRUE(earth_g);
  // The text names the terms and the pairs.
  const auto text = run_cli({"calibrate", d.file("r5.csv"), "--pairing", "harmonic"});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("inseparable: Earth rate and g-sensitivity"), std::string::npos);
  EXPECT_NE(text.out.find("  s2 "), std::string::npos);
  // Before a run: three positions alias the second harmonic onto the first.
  const auto e = run_cli({"calibrate", "--explain", "--positions", "0,120,240", "--json"});
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const auto x = json::parse(e.out);
  EXPECT_EQ(x["schema"], "gyroflip.separability/1");
  EXPECT_EQ(x["estimable"], json::array({"b", "c1", "s1"}));
  const auto up =
      run_cli({"calibrate", "--explain", "--positions", "0,90,180,270", "--table-axis", "up"});
  ASSERT_EQ(up.exit_code, 0) << up.err;
  EXPECT_NE(up.out.find("table tilt x g-sensitivity"), std::string::npos);
  EXPECT_NE(up.out.find("not observable: s2"), std::string::npos);
  // --explain with neither a table nor recordings: a usage error (exit 2).
  EXPECT_EQ(run_cli({"calibrate", "--explain"}).exit_code, 2);
}

namespace {

// The `# terms_dps` line of a truth file: c1, s1, c2, s2 (Earth + g-term, deg/s).
std::map<std::string, double> truth_terms(const std::string& truth_file) {
  const std::string text = read_text(truth_file);
  const auto at = text.find("# terms_dps");
  EXPECT_NE(at, std::string::npos) << truth_file;
  std::map<std::string, double> out;
  if (at == std::string::npos) return out;
  const auto from = text.find(':', at) + 1;
  std::istringstream line(text.substr(from, text.find('\n', at) - from));
  std::string name;
  double v = 0.0;
  while (line >> name >> v && out.size() < 4) out[name] = v;
  return out;
}

}  // namespace

// Issue 33: `simulate --truth` writes every harmonic term, c2 and s2 as well as c1 and s1, for
// any table. A long five-position run (4 h, fixed seed): `calibrate --pairing harmonic` (which
// is fit_harmonics over the run) finds each of c1, s1, c2, s2 within 4 of its own sigma of the
// truth file's. A 0/180 table at azimuth 30 deg about a vertical axis has the closed form
// c1 = W_H cos 30, s1 = W_H sin 30 (within the preset's cross-axis share, 3 %): the first
// harmonic over the whole turn, which two positions alone do not determine.
TEST(CliSimulate, TheTruthHoldsBothHarmonicsForAnyTable) {
  temp_dir d;
  const auto sim =
      run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "14400", "--seed", "8",
               "--positions", "0,72,144,216,288", "--latitude", "42.6", "--azimuth", "30",
               "--tilt-mrad", "2", "-o", d.file("r.csv"), "--truth", d.file("t.csv")});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto truth = truth_terms(d.file("t.csv"));
  ASSERT_EQ(truth.size(), 4U);
  EXPECT_LT(std::abs(truth.at("c2")), 1e-15);
  EXPECT_LT(std::abs(truth.at("s2")), 1e-15);
  const auto r = run_cli({"calibrate", d.file("r.csv"), "--pairing", "harmonic", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::size_t checked = 0;
  const auto j = json::parse(r.out);
  for (const auto& t : j["terms"]) {
    const std::string name = t["name"];
    if (name == "b") continue;
    const double se = t["stderr_correlated_dps"].get<double>();
    EXPECT_GT(se, 0.0) << name;
    EXPECT_LT(se, 2e-4) << name;
    EXPECT_NEAR(t["value_dps"].get<double>(), truth.at(name), 4.0 * se) << name;
    ++checked;
  }
  EXPECT_EQ(checked, 4U);

  const auto two =
      run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "30", "--positions", "0,180",
               "--latitude", "42.6", "--table-axis", "up", "--azimuth", "30", "-o",
               d.file("r2.csv"), "--truth", d.file("t2.csv")});
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const auto t2 = truth_terms(d.file("t2.csv"));
  ASSERT_EQ(t2.size(), 4U);
  const double w_h = earth::earth_rate_wgs84_dps * std::cos(42.6 * M_PI / 180.0);
  EXPECT_NEAR(t2.at("c1"), w_h * std::cos(M_PI / 6.0), 0.03 * w_h);
  EXPECT_NEAR(t2.at("s1"), w_h * std::sin(M_PI / 6.0), 0.03 * w_h);
  EXPECT_LT(std::hypot(t2.at("c2"), t2.at("s2")), 1e-15);
  // The paper's plain 0/180 run has its terms too.
  ASSERT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "30", "-o",
                     d.file("r3.csv"), "--truth", d.file("t3.csv")})
                .exit_code,
            0);
  EXPECT_EQ(truth_terms(d.file("t3.csv")).size(), 4U);
}

// Issue 33: `compensate` with a calibration of the harmonic scheme applies its terms at each
// position. A four-position calibration about the paper's horizontal table axis (the sensitive
// axis north at table 0, so c1 = W_E cos(lat) and s1 = -+W_E sin(lat): at 90 deg the axis points
// down or up; at 42.6 deg S they differ by 0.0055 deg/s), then independent runs (other seeds): a
// 90/270 pair is compensated with c1 cos 90 + s1 sin 90 = s1, its mean 0 within 4 sigma of its
// errors (the old code refused the pair: the calibration's harmonic pairing needs three
// positions; with --pairing abba it subtracted c1, some 15 sigma off); a four-position run with
// the terms at each position.
TEST(CliCompensate, AHarmonicCalibrationAppliesItsTermsAtEachPosition) {
  temp_dir d;
  const auto sim = [&](const std::string& positions, const std::string& seed,
                       const std::string& duration, const std::string& out) {
    const auto r = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", duration, "--seed",
                            seed, "--positions", positions, "--latitude", "-42.6", "--axis",
                            "north", "-o", d.file(out), "--truth", d.file("t" + out)});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  };
  sim("0,90,180,270", "21", "3600", "cal4.csv");
  const auto cal =
      run_cli({"calibrate", d.file("cal4.csv"), "--pairing", "harmonic", "-o", d.file("cal.json")});
  ASSERT_EQ(cal.exit_code, 0) << cal.err;
  const auto truth = truth_terms(d.file("tcal4.csv"));
  ASSERT_GT(std::abs(truth.at("s1") - truth.at("c1")), 0.004);  // tells c1 from s1
  // The 0/180 pair at 90/270 deg.
  sim("90,270", "22", "1200", "pair.csv");
  const auto p =
      run_cli({"compensate", d.file("pair.csv"), "--calibration", d.file("cal.json"), "--json"});
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_NE(p.err.find("harmonic terms"), std::string::npos) << p.err;
  const auto pj = json::parse(p.out);
  EXPECT_EQ(pj["pairing"], "abba");
  const auto cj = json::parse(read_text(d.file("cal.json")));
  double s1 = 0.0, s1_se = 0.0;
  for (const auto& t : cj["terms"])
    if (t["name"] == "s1") {
      s1 = t["value_dps"].get<double>();
      s1_se = t["stderr_correlated_dps"].get<double>();
    }
  EXPECT_NEAR(pj["delta_n"]["delta_n_dps"].get<double>(), s1, 1e-12);  // sin 90 = 1, cos 90 = 0
  EXPECT_TRUE(pj["delta_n"]["terms_dps"].contains("s1"));
  const double se_p = pj["stderr_correlated_dps"].get<double>();
  EXPECT_NEAR(pj["mean_dps"].get<double>(), 0.0, 4.0 * std::hypot(se_p, s1_se)) << p.out;
  // Four positions: the harmonic pairing, the terms at each position.
  sim("0,90,180,270", "23", "1200", "run4.csv");
  const auto q =
      run_cli({"compensate", d.file("run4.csv"), "--calibration", d.file("cal.json"), "--json"});
  ASSERT_EQ(q.exit_code, 0) << q.err;
  const auto qj = json::parse(q.out);
  EXPECT_EQ(qj["pairing"], "harmonic");
  double c1_se = 0.0;
  for (const auto& t : cj["terms"])
    if (t["name"] == "c1") c1_se = t["stderr_correlated_dps"].get<double>();
  EXPECT_NEAR(qj["mean_dps"].get<double>(), 0.0,
              4.0 * std::hypot(qj["stderr_correlated_dps"].get<double>(), c1_se))
      << q.out;
}

// The error compensate quotes for a harmonic calibration applied to a 0/180 pair at theta is
// that of c1 cos theta + s1 sin theta with the terms' full covariance, scaled so that c1's is the
// budget's, plus c1's run-to-run part (workflow::pair_errors_of). A three-position calibration at
// 0/45/180 deg knows s1 from one position only: its s1 is ~5 times c1's error and correlated with
// it. At 0/180 the quote is c1's; at 90/270 and 45/225 the delta method's (before: c1's at every
// angle, 0.0005 deg/s where s1 alone carries ~5 times that).
TEST(CliCompensate, APairAtAnyAngleQuotesTheErrorOfItsHarmonicCombination) {
  temp_dir d;
  const auto sim = [&](const std::string& positions, const std::string& seed,
                       const std::string& duration, const std::string& out) {
    const auto r = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", duration, "--seed",
                            seed, "--positions", positions, "-o", d.file(out)});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  };
  sim("0,45,180", "31", "1800", "cal3.csv");
  ASSERT_EQ(
      run_cli({"calibrate", d.file("cal3.csv"), "--pairing", "harmonic", "-o", d.file("cal.json")})
          .exit_code,
      0);
  const auto cj = json::parse(read_text(d.file("cal.json")));
  const auto& names = cj["terms"];
  const std::size_t n = names.size();
  std::size_t i1 = n, i2 = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (names[i]["name"] == "c1") i1 = i;
    if (names[i]["name"] == "s1") i2 = i;
  }
  ASSERT_LT(i1, n);
  ASSERT_LT(i2, n);
  const auto cov = cj["terms_covariance"].get<std::vector<std::vector<double>>>();  // rows
  ASSERT_EQ(cov.size(), n);
  const double v11 = cov[i1][i1], v22 = cov[i2][i2], v12 = cov[i1][i2];
  ASSERT_GT(v22, 4.0 * v11);                              // s1 known far worse than c1
  ASSERT_GT(std::abs(v12), 0.05 * std::sqrt(v11 * v22));  // and correlated with it
  const auto errors = [&](const std::string& positions, const std::string& seed) {
    sim(positions, seed, "300", "p" + seed + ".csv");
    const auto r = run_cli(
        {"compensate", d.file("p" + seed + ".csv"), "--calibration", d.file("cal.json"), "--json"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const auto j = json::parse(r.out)["delta_n"];
    return std::pair{j["error_dps"].get<double>(), j["new_power_up_dps"].get<double>()};
  };
  const auto [u1, np1] = errors("0,180", "32");  // c1's own: the calibration's quote
  ASSERT_GT(u1, 0.0);
  ASSERT_GE(np1, u1);
  for (const auto& [positions, theta_deg] :
       std::vector<std::pair<std::string, double>>{{"90,270", 90.0}, {"45,225", 45.0}}) {
    const double c = std::cos(theta_deg * M_PI / 180.0), s = std::sin(theta_deg * M_PI / 180.0);
    const double var = u1 * u1 / v11 * (c * c * v11 + s * s * v22 + 2.0 * s * c * v12);
    const auto [u, np] = errors(positions, positions == "90,270" ? "33" : "34");
    EXPECT_NEAR(u, std::sqrt(var), 1e-9 * std::sqrt(var)) << positions;
    EXPECT_NEAR(np, std::sqrt(var + np1 * np1 - u1 * u1), 1e-9 * np) << positions;
  }
}

// The same at each position, where the old way (the calibration's c1 taken from each period's
// c1) cannot: a second harmonic c2 of a five-position calibration aliases into c1 on a run at
// 0/120/240 deg (cos 2t = cos t there). Synthetic dwells (closed form plus white noise, fixed
// stream), c1 3e-3, s1 -1e-3, c2 2e-3 deg/s and no input: the compensated mean is 0 within 4 sigma
// (subtracting c1 alone leaves c2, 2e-3, hundreds of sigma).
TEST(CliCompensate, HarmonicTermsAreRemovedAtEachPositionBeforeTheyCanAlias) {
  temp_dir d;
  std::uint64_t state = 99;
  const auto uniform = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) + 0.5) / 9007199254740992.0;
  };
  const auto write = [&](const std::string& name, const std::vector<double>& pos) {
    std::string text = "# positions_deg: ";
    for (std::size_t i = 0; i < pos.size(); ++i) {
      if (i > 0) text += ',';
      text += fmt::format("{}", pos[i]);
    }
    text += "\n# conversion_time_s: 0.002\ntime_s,angle_deg,rate_dps,n_avg\n";
    std::vector<double> order(pos);
    order.insert(order.end(), pos.rbegin(), pos.rend());  // the sweep, each end twice
    double t = 0.5;
    for (int b = 0; b < 300; ++b)
      for (const double a : order) {
        const double th = a * M_PI / 180.0;
        const double n = std::sqrt(-2 * std::log(uniform())) * std::cos(2 * M_PI * uniform());
        const double r =
            0.01 + 3e-3 * std::cos(th) - 1e-3 * std::sin(th) + 2e-3 * std::cos(2 * th) + 2e-4 * n;
        text += fmt::format("{},{},{:.12g},500\n", t, a, r);
        t += 1.2;
      }
    write_text(d.file(name), text);
  };
  write("five.csv", {0, 72, 144, 216, 288});
  write("three.csv", {0, 120, 240});
  ASSERT_EQ(
      run_cli({"calibrate", d.file("five.csv"), "--pairing", "harmonic", "-o", d.file("cal5.json")})
          .exit_code,
      0);
  const auto r =
      run_cli({"compensate", d.file("three.csv"), "--calibration", d.file("cal5.json"), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = json::parse(r.out);
  EXPECT_EQ(j["pairing"], "harmonic");
  const double se = j["stderr_correlated_dps"].get<double>();
  EXPECT_LT(se, 1e-4);
  EXPECT_NEAR(j["mean_dps"].get<double>(), 0.0, 4.0 * std::hypot(se, 3e-5)) << r.out;
}

// Issue 33 item 2: `simulate --order there-and-back` visits the positions as `record` has the
// device visit them (0,1,2,3,2,1: its angle table), the rows naming each position by its angle;
// what the device cannot hold is refused (exit 2): one-way turns, more than five positions.
TEST(CliSimulate, ThereAndBackIsTheDevicesVisitingOrder) {
  temp_dir d;
  const auto sim =
      run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "30", "--positions",
               "0,90,180,270", "--order", "there-and-back", "-o", d.file("tb.csv")});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  std::istringstream in(read_text(d.file("tb.csv")));
  std::string line;
  while (std::getline(in, line) && line.rfind('#', 0) == 0) {
  }
  ASSERT_EQ(line.substr(0, 15), "time_s,angle_de");
  std::vector<double> angles;
  while (std::getline(in, line)) {
    const auto a = line.find(',');
    angles.push_back(std::stod(line.substr(a + 1)));
  }
  ASSERT_GE(angles.size(), 24U);
  const std::vector<double> period{0, 90, 180, 270, 180, 90};
  for (std::size_t k = 0; k < angles.size(); ++k)
    ASSERT_EQ(angles[k], period[k % period.size()]) << "row " << k;
  for (const auto& bad : std::vector<std::vector<std::string>>{
           {"--positions", "0,90,180,270", "--one-way"}, {"--positions", "0,36,72,108,144,180"}}) {
    std::vector<std::string> args{"simulate",       "--sensor", "hz1-90-100a",
                                  "--duration",     "10",       "--order",
                                  "there-and-back", "-o",       d.file("bad.csv")};
    args.insert(args.end(), bad.begin(), bad.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("there-and-back"), std::string::npos) << r.err;
  }
}

}  // namespace gyroflip::test
