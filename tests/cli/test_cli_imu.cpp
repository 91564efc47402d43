// Accelerometer records and Kalibr's IMU file (issue 34 item 3): simulated records with known
// white-noise densities N and random walks K, their terms in the field's units, and the Kalibr
// file read with the rules of Kalibr's own reader (tests/support/kalibr_imu_rules.py).
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/ros_bags.hpp"
#include "support/run_cli.hpp"
#include "support/synth.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

using nlohmann::json;
constexpr double pi = 3.14159265358979323846;
constexpr double rad_per_deg = pi / 180.0;
constexpr double rate_hz = 50.0;
constexpr std::size_t samples = 180000;  // 1 h

// The truth: gyro columns in deg/s (N deg/s/sqrt(Hz), K deg/s/sqrt(s)), accelerometer columns in
// m/s^2 (N m/s^2/sqrt(Hz), K m/s^3/sqrt(Hz)); a different largest axis for each term.
constexpr std::array gyro_n{0.006, 0.004, 0.003};
constexpr std::array gyro_k{1.0e-4, 1.5e-4, 3.0e-4};
constexpr std::array accel_n{0.0015, 0.003, 0.002};
constexpr std::array accel_k{4.0e-4, 2.0e-4, 2.5e-4};

// White noise of density n plus a random walk of density k, sampled every 1/rate_hz.
std::vector<double> white_plus_walk(double n, double k, std::uint64_t seed) {
  normal_source g(seed);
  const double dt = 1.0 / rate_hz;
  std::vector<double> y(samples);
  double walk = 0.0;
  for (auto& v : y) {
    walk += k * std::sqrt(dt) * g();
    v = n / std::sqrt(dt) * g() + walk;
  }
  return y;
}

struct imu_record {
  std::array<std::vector<double>, 3> gyro_dps, accel_mps2;
};

imu_record simulate(std::uint64_t seed) {
  imu_record r;
  for (std::size_t i = 0; i < 3; ++i) {
    r.gyro_dps[i] = white_plus_walk(gyro_n[i], gyro_k[i], seed + i);
    r.accel_mps2[i] = white_plus_walk(accel_n[i], accel_k[i], seed + 10 + i);
  }
  return r;
}

// CSV with a time column and the named columns, each scaled.
std::string csv(const std::vector<std::string>& names,
                const std::vector<const std::vector<double>*>& cols,
                const std::vector<double>& scale) {
  std::string s = "time_s";
  for (const auto& n : names) s += "," + n;
  s += "\n";
  for (std::size_t k = 0; k < samples; ++k) {
    s += fmt::format("{:.6f}", static_cast<double>(k) / rate_hz);
    for (std::size_t c = 0; c < cols.size(); ++c)
      s += fmt::format(",{:.9g}", (*cols[c])[k] * scale[c]);
    s += "\n";
  }
  return s;
}

json run_json(const std::vector<std::string>& args) {
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? json::parse(r.out) : json::object();
}

bool have_pyyaml() {
  return std::system("python3 -c 'import yaml' 2>/dev/null") == 0;
}

// The Kalibr file's values as Kalibr's reader rules read them (exit code, values).
std::pair<int, json> kalibr_read(const temp_dir& dir, const std::string& yaml) {
  const std::string out = dir.file("kalibr_values.json");
  std::remove(out.c_str());
  const std::string script = std::string(GYROFLIP_VECTORS_DIR) + "/../support/kalibr_imu_rules.py";
  const int rc = std::system(("python3 " + script + " " + yaml + " " + out).c_str());
  return {rc, rc == 0 ? json::parse(read_text(out)) : json::object()};
}

// One file with gyro (deg/s) and accelerometer (m/s^2) columns, the units in the names: made
// once for the suite (writing 1 h at 50 Hz costs more than analysing it).
struct fixture {
  temp_dir dir;
  imu_record rec = simulate(3401);
  std::string file = dir.file("imu.csv");
  fixture() {
    write_text(file, csv({"gx_dps", "gy_dps", "gz_dps", "ax_mps2", "ay_mps2", "az_mps2"},
                         {&rec.gyro_dps[0], &rec.gyro_dps[1], &rec.gyro_dps[2], &rec.accel_mps2[0],
                          &rec.accel_mps2[1], &rec.accel_mps2[2]},
                         {1, 1, 1, 1, 1, 1}));
  }
};
const fixture& shared() {
  static const fixture f;
  return f;
}

// A term's value, or its upper limit when the data do not resolve it.
double value_or_upper(const json& j, const std::string& key) {
  return j[key].is_number() ? j[key].get<double>() : j[key + "_upper"].get<double>();
}

// Accelerometer columns found by the unit in their names, in m/s^2, g and mg units: VRW and the
// acceleration random walk within stated tolerances of the truth (1 h at 50 Hz: N to 3 %, K to
// 35 %, about 3 sigma of each estimate over seeds 3401-3405) and inside their intervals; a record
// in mg gives the same terms.
TEST(CliImu, AccelerometerTermsFromTheColumnsUnitMatchTheTruth) {
  const auto& f = shared();
  const json all = run_json({"noise", f.file, "--columns", "all-numeric", "--json"});
  ASSERT_EQ(all["columns"].size(), 6u);
  for (std::size_t i = 0; i < 3; ++i) {
    const json& g = all["columns"][i];
    const json& a = all["columns"][i + 3];
    EXPECT_EQ(g["quantity"], "gyro");
    EXPECT_EQ(a["quantity"], "accel");
    EXPECT_EQ(a["units"], "m/s^2");
    EXPECT_NEAR(a["vrw_mps2_rthz"].get<double>() / accel_n[i], 1.0, 0.03) << i;
    EXPECT_NEAR(a["acceleration_rw_mps3_rthz"].get<double>() / accel_k[i], 1.0, 0.35) << i;
    EXPECT_LE(a["vrw_mps2_rthz_lo"].get<double>(), accel_n[i] * 1.001);
    EXPECT_GE(a["vrw_mps2_rthz_hi"].get<double>(), accel_n[i] * 0.999);
    // The same N in the other units: m/s/sqrt(h) = 60 m/s^2/sqrt(Hz); ug = 1e6/9.80665.
    EXPECT_NEAR(a["vrw_mps_rth"].get<double>() / a["vrw_mps2_rthz"].get<double>(), 60.0, 1e-9);
    EXPECT_NEAR(a["vrw_ug_rthz"].get<double>() / a["vrw_mps2_rthz"].get<double>(), 1e6 / 9.80665,
                1e-6);
    EXPECT_NEAR(g["arw_dps_rthz"].get<double>() / gyro_n[i], 1.0, 0.03) << i;
    EXPECT_FALSE(a.contains("arw_dps_rthz"));
  }
  // The same record in mg, named by a bracketed unit, and in g through --quantity/--units.
  const auto& x = f.rec.accel_mps2[0];
  write_text(f.dir.file("mg.csv"), csv({"acc_x [mg]"}, {&x}, {1e3 / 9.80665}));
  write_text(f.dir.file("g.csv"), csv({"x"}, {&x}, {1.0 / 9.80665}));
  const json mg = run_json({"noise", f.dir.file("mg.csv"), "--column", "acc_x [mg]", "--json"});
  const json g = run_json({"noise", f.dir.file("g.csv"), "--column", "x", "--quantity", "accel",
                           "--units", "g", "--json"});
  for (const json* j : {&mg, &g}) {
    EXPECT_EQ((*j)["quantity"], "accel");
    EXPECT_NEAR(
        (*j)["vrw_mps2_rthz"].get<double>() / all["columns"][3]["vrw_mps2_rthz"].get<double>(), 1.0,
        1e-6);
    EXPECT_NEAR(
        (*j)["bias_floor_mg"].get<double>() / all["columns"][3]["bias_floor_mg"].get<double>(), 1.0,
        1e-6);
  }
  // The text names the accelerometer's terms.
  const auto text = run_cli({"noise", f.dir.file("mg.csv"), "--column", "acc_x [mg]"});
  EXPECT_NE(text.out.find("velocity random walk N"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("acceleration random walk K"), std::string::npos) << text.out;
  // A contradiction is refused, naming the column: an accelerometer column with a gyro unit.
  const auto bad = run_cli({"noise", f.file, "--column", "ax_mps2", "--units", "deg/s"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("column ax_mps2 is named in m/s^2"), std::string::npos) << bad.err;
  const auto bad_q = run_cli({"noise", f.file, "--column", "gx_dps", "--quantity", "accel"});
  EXPECT_EQ(bad_q.exit_code, 2);
  EXPECT_NE(bad_q.err.find("not of --quantity accel"), std::string::npos) << bad_q.err;
}

// Kalibr's file from one record with both sensors: every key Kalibr's reader requires, in its
// units (gyro rad), each the largest axis, and the truth within the tolerances above.
TEST(CliImu, KalibrFileFromOneRecordLoadsAndHoldsTheTruth) {
  if (!have_pyyaml()) GTEST_SKIP() << "python3-yaml is not installed (scripts/setup installs it)";
  const auto& f = shared();
  const std::string yaml = f.dir.file("imu.yaml");
  const json all = run_json({"noise", f.file, "--columns", "all-numeric", "--kalibr", yaml,
                             "--rostopic", "/vi_sensor/imu", "--json"});
  const auto [rc, k] = kalibr_read(f.dir, yaml);
  ASSERT_EQ(rc, 0) << read_text(yaml);
  EXPECT_EQ(k["rostopic"], "/vi_sensor/imu");
  EXPECT_DOUBLE_EQ(k["update_rate"].get<double>(), rate_hz);
  // The largest axis of each term, as the JSON has it (6 significant digits in the file).
  const auto largest = [&](std::size_t first, const char* key) {
    double v = 0.0;
    for (std::size_t i = first; i < first + 3; ++i)
      v = std::max(v, value_or_upper(all["columns"][i], key));
    return v;
  };
  EXPECT_NEAR(k["gyroscope_noise_density"].get<double>() / largest(0, "arw_rad_s_rthz"), 1.0, 1e-6);
  EXPECT_NEAR(k["gyroscope_random_walk"].get<double>() / largest(0, "rrw_rad_s2_rthz"), 1.0, 1e-6);
  EXPECT_NEAR(k["accelerometer_noise_density"].get<double>() / largest(3, "vrw_mps2_rthz"), 1.0,
              1e-6);
  EXPECT_NEAR(
      k["accelerometer_random_walk"].get<double>() / largest(3, "acceleration_rw_mps3_rthz"), 1.0,
      1e-6);
  // Against the truth: the largest true axis (x for gyro N, z for gyro K, y for accel N, x for
  // accel K).
  EXPECT_NEAR(k["gyroscope_noise_density"].get<double>() / (gyro_n[0] * rad_per_deg), 1.0, 0.03);
  EXPECT_NEAR(k["gyroscope_random_walk"].get<double>() / (gyro_k[2] * rad_per_deg), 1.0, 0.35);
  EXPECT_NEAR(k["accelerometer_noise_density"].get<double>() / accel_n[1], 1.0, 0.03);
  EXPECT_NEAR(k["accelerometer_random_walk"].get<double>() / accel_k[0], 1.0, 0.35);
  // Kalibr's discrete-time density: N sqrt(rate).
  EXPECT_NEAR(k["gyroscope_noise_density_discrete"].get<double>() /
                  k["gyroscope_noise_density"].get<double>(),
              std::sqrt(rate_hz), 1e-9);
  // The axes' values are comments in the file.
  EXPECT_NE(read_text(yaml).find("# gyroscope_noise_density per axis"), std::string::npos);
}

// The same file from two records (gyro, then the accelerometer's with --kalibr-other) holds the
// same values; without accelerometer columns, or at two rates, nothing is written (exit 2).
TEST(CliImu, KalibrFileFromTwoRecordsAndWhatIsRefused) {
  if (!have_pyyaml()) GTEST_SKIP() << "python3-yaml is not installed (scripts/setup installs it)";
  const auto& f = shared();
  const auto& r = f.rec;
  // The gyro in rad/s with plain names (--units), the accelerometer in g named by its unit.
  const double to_rad = rad_per_deg;
  write_text(f.dir.file("gyro.csv"),
             csv({"wx", "wy", "wz"}, {&r.gyro_dps[0], &r.gyro_dps[1], &r.gyro_dps[2]},
                 {to_rad, to_rad, to_rad}));
  const double to_g = 1.0 / 9.80665;
  write_text(f.dir.file("accel.csv"),
             csv({"ax_g", "ay_g", "az_g"}, {&r.accel_mps2[0], &r.accel_mps2[1], &r.accel_mps2[2]},
                 {to_g, to_g, to_g}));
  const std::string one = f.dir.file("one.yaml"), two = f.dir.file("two.yaml");
  ASSERT_EQ(run_cli({"noise", f.file, "--columns", "all-numeric", "--kalibr", one}).exit_code, 0);
  const auto both = run_cli({"noise", f.dir.file("gyro.csv"), "--column", "wx,wy,wz", "--units",
                             "rad/s", "--kalibr", two, "--kalibr-other", f.dir.file("accel.csv")});
  ASSERT_EQ(both.exit_code, 0) << both.err;
  const auto [rc1, k1] = kalibr_read(f.dir, one);
  const auto [rc2, k2] = kalibr_read(f.dir, two);
  ASSERT_EQ(rc1, 0);
  ASSERT_EQ(rc2, 0) << read_text(two);
  for (const char* key : {"gyroscope_noise_density", "gyroscope_random_walk",
                          "accelerometer_noise_density", "accelerometer_random_walk"})
    EXPECT_NEAR(k2[key].get<double>() / k1[key].get<double>(), 1.0, 2e-6) << key;
  // A gyro alone cannot make a file Kalibr loads: refused, nothing written.
  const std::string none = f.dir.file("none.yaml");
  const auto gyro_only = run_cli(
      {"noise", f.dir.file("gyro.csv"), "--column", "wx", "--units", "rad/s", "--kalibr", none});
  EXPECT_EQ(gyro_only.exit_code, 2);
  EXPECT_NE(gyro_only.err.find("has no accelerometer column"), std::string::npos) << gyro_only.err;
  EXPECT_FALSE(std::ifstream(none).good());
  // Two rates: Kalibr has one update_rate.
  std::string slow = "time_s,ax_mps2\n";
  for (std::size_t k = 0; k < samples / 2; ++k)
    slow += fmt::format("{:.6f},{:.9g}\n", static_cast<double>(k) / 25.0, r.accel_mps2[0][2 * k]);
  write_text(f.dir.file("slow.csv"), slow);
  const auto rates = run_cli({"noise", f.dir.file("gyro.csv"), "--column", "wx", "--units", "rad/s",
                              "--kalibr", none, "--kalibr-other", f.dir.file("slow.csv")});
  EXPECT_EQ(rates.exit_code, 2);
  EXPECT_NE(rates.err.find("Kalibr has one update_rate"), std::string::npos) << rates.err;
  EXPECT_FALSE(std::ifstream(none).good());
}

// Real logs lose messages (issue 34 item 4): three single messages lost in an hour, at 10 %, 37 %
// and 81 % of it. --gaps split analyses the longest run (44 % of the data); --gaps fill bridges
// the 3 samples (0.0017 %) and keeps every measured sample: its N is the gap-free record's within
// 0.2 % (bridging 3 of 180000 samples moves ADEV(tau0) by about 3/180000), and the truth's within
// the suite's 3 %. Without --gaps the error points to fill.
TEST(CliImu, ThreeLostMessagesInAnHourKeepEverySampleWithFill) {
  const auto& f = shared();
  const auto& x = f.rec.gyro_dps[0];
  std::string text = "time_s,gx_dps\n";
  for (std::size_t k = 0; k < samples; ++k)
    if (k != 18000 && k != 66600 && k != 145800)
      text += fmt::format("{:.6f},{:.9g}\n", static_cast<double>(k) / rate_hz, x[k]);
  const std::string lossy = f.dir.file("lossy.csv");
  write_text(lossy, text);
  const auto refused = run_cli({"noise", lossy, "--column", "gx_dps"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("3 gaps"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("fill"), std::string::npos) << refused.err;
  const json split = run_json({"noise", lossy, "--column", "gx_dps", "--gaps", "split", "--json"});
  EXPECT_EQ(split["samples"].get<double>(), 145800.0 - 66601.0);  // 44 % of the hour
  const auto filled = run_cli({"noise", lossy, "--column", "gx_dps", "--gaps", "fill", "--json"});
  ASSERT_EQ(filled.exit_code, 0) << filled.err;
  EXPECT_NE(filled.err.find("3 samples (0.00167 % of 180000) bridged by linear interpolation"),
            std::string::npos)
      << filled.err;
  const json fill = json::parse(filled.out);
  EXPECT_EQ(fill["samples"].get<double>(), static_cast<double>(samples));
  const json whole = run_json({"noise", f.file, "--column", "gx_dps", "--json"});
  EXPECT_NEAR(fill["arw_dps_rthz"].get<double>() / whole["arw_dps_rthz"].get<double>(), 1.0, 2e-3);
  EXPECT_NEAR(fill["arw_dps_rthz"].get<double>() / gyro_n[0], 1.0, 0.03);
}

// A ROS 1 bag's IMU topic (20 min of the suite's record at 50 Hz in rad/s and m/s^2, written by
// tests/support/ros_bags.cpp): the bag's only IMU topic taken, both sensors' units read from the
// column names, N of each axis within 5 % of the truth (about 3 sigma at 20 min), and Kalibr's
// file with the topic read as its rostopic; a wrong column suggests the right one.
TEST(CliImu, ARosBagsImuTopicGivesBothSensorsAndKalibrsRostopic) {
  if (!have_pyyaml()) GTEST_SKIP() << "python3-yaml is not installed (scripts/setup installs it)";
  const auto& f = shared();
  constexpr std::size_t n = 60000;
  bag_topic imu{"/imu/data", "sensor_msgs/Imu", {}, "imu_link"};
  bag_topic status{"/status", "std_msgs/UInt32", {}, ""};
  for (std::size_t k = 0; k < n; ++k) {
    imu_msg m;
    const std::uint64_t ns = 1700000000000000000ULL + k * 20000000ULL;
    m.sec = static_cast<std::uint32_t>(ns / 1000000000ULL);
    m.nsec = static_cast<std::uint32_t>(ns % 1000000000ULL);
    for (std::size_t i = 0; i < 3; ++i) {
      m.gyro_rad_s[i] = f.rec.gyro_dps[i][k] * rad_per_deg;
      m.accel_m_s2[i] = f.rec.accel_mps2[i][k];
    }
    imu.messages.push_back(m);
    if (k % 50 == 0) status.messages.push_back(m);
  }
  const std::string bag = f.dir.file("imu.bag");
  write_ros1_bag(bag, {imu, status});
  const std::string yaml = f.dir.file("bag.yaml");
  const auto r = run_cli({"noise", bag, "--columns", "all-numeric", "--kalibr", yaml, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json all = json::parse(r.out);
  ASSERT_EQ(all["columns"].size(), 6U);
  for (std::size_t i = 0; i < 3; ++i) {
    const json& g = all["columns"][i];
    const json& a = all["columns"][i + 3];
    EXPECT_EQ(g["units"], "rad/s") << i;
    EXPECT_EQ(a["quantity"], "accel") << i;
    EXPECT_NEAR(g["arw_dps_rthz"].get<double>() / gyro_n[i], 1.0, 0.05) << i;
    EXPECT_NEAR(a["vrw_mps2_rthz"].get<double>() / accel_n[i], 1.0, 0.05) << i;
  }
  const auto [rc, k] = kalibr_read(f.dir, yaml);
  ASSERT_EQ(rc, 0) << read_text(yaml);
  EXPECT_EQ(k["rostopic"], "/imu/data");
  EXPECT_DOUBLE_EQ(k["update_rate"].get<double>(), rate_hz);
  const auto wrong = run_cli({"adev", bag + ":/imu/data", "--column", "gyro_x"});
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("did you mean 'gyro_x_rad_s'?"), std::string::npos) << wrong.err;
  const auto csv_wrong = run_cli({"noise", f.file, "--column", "gx"});
  EXPECT_EQ(csv_wrong.exit_code, 2);
  EXPECT_NE(csv_wrong.err.find("did you mean 'gx_dps'?"), std::string::npos) << csv_wrong.err;
}

}  // namespace
}  // namespace gyroflip::test
