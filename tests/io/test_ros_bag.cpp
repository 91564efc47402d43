// ROS bags (issue 34 item 4): sensor_msgs/Imu from ROS 1 .bag (format 2.0) and ROS 2 .db3
// (SQLite, CDR), written by the test from the formats' specifications (support/ros_bags.hpp) with
// known values and stamps; the topic chosen, the columns, the header stamps as time, gaps found,
// filled or split; bad bags are errors naming the file and the record.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "gyroflip/io/ros_bag.hpp"
#include "gyroflip/io/series.hpp"
#include "support/ros_bags.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

constexpr std::uint32_t t0_sec = 1700000000;
constexpr std::uint32_t t0_nsec = 123456789;
constexpr std::uint32_t step_ns = 5000000;  // 200 Hz

// Message k's values: distinct per axis, not on any grid the reader could produce by itself.
imu_msg truth(std::size_t k) {
  const double x = static_cast<double>(k);
  imu_msg m;
  const std::uint64_t ns = std::uint64_t{t0_nsec} + k * std::uint64_t{step_ns};
  m.sec = t0_sec + static_cast<std::uint32_t>(ns / 1000000000);
  m.nsec = static_cast<std::uint32_t>(ns % 1000000000);
  m.gyro_rad_s = {0.01 * std::sin(0.1 * x), -0.02 * std::cos(0.07 * x), 1e-4 * x};
  m.accel_m_s2 = {0.1 * std::sin(0.3 * x), 0.2 + 1e-5 * x, 9.80665 - 1e-3 * std::cos(x)};
  return m;
}

std::vector<bag_topic> three_topics(std::size_t n, const std::vector<std::size_t>& dropped = {}) {
  bag_topic imu{"/imu/data", "sensor_msgs/Imu", {}, "imu_link"};
  bag_topic raw{"/imu/raw", "sensor_msgs/Imu", {}, "x"};
  bag_topic other{"/status", "std_msgs/UInt32", {}, ""};
  for (std::size_t k = 0; k < n; ++k) {
    if (std::find(dropped.begin(), dropped.end(), k) == dropped.end())
      imu.messages.push_back(truth(k));
    if (k % 10 == 0) {
      imu_msg r = truth(k);
      r.gyro_rad_s = {7.0, 7.0, 7.0};
      raw.messages.push_back(r);
      other.messages.push_back(r);
    }
  }
  return {imu, raw, other};
}

void expect_truth(const io::imu_table& t, std::size_t n) {
  ASSERT_EQ(t.time_s.size(), n);
  EXPECT_EQ(t.topic, "/imu/data");
  for (std::size_t k = 0; k < n; ++k) {
    const auto m = truth(k);
    for (std::size_t i = 0; i < 3; ++i) {
      ASSERT_EQ(t.values[i][k], m.gyro_rad_s[i]) << k;
      ASSERT_EQ(t.values[3 + i][k], m.accel_m_s2[i]) << k;
    }
    // Stamps rebased in integer ns: exact to the double's rounding of k * 5 ms.
    ASSERT_NEAR(t.time_s[k], 0.005 * static_cast<double>(k), 1e-12) << k;
  }
}

struct bag_kind {
  const char* name;
  bool ros2;
  bool big_endian;
};

class Bags : public ::testing::TestWithParam<bag_kind> {
 protected:
  void write(const std::string& path, const std::vector<bag_topic>& topics) {
    if (GetParam().ros2)
      write_ros2_bag(path, topics, GetParam().big_endian);
    else
      write_ros1_bag(path, topics);
  }
  [[nodiscard]] std::string name(const std::string& stem) const {
    return d_.file(stem + (GetParam().ros2 ? ".db3" : ".bag"));
  }
  temp_dir d_;
};

TEST_P(Bags, TheNamedTopicsMessagesOnTheirHeaderStamps) {
  const std::string path = name("a");
  write(path, three_topics(1000));
  auto t = io::read_imu_bag(path, "/imu/data");
  ASSERT_TRUE(t) << t.err().message;
  expect_truth(*t, 1000);
  // As series: FILE:/topic, any columns by name or message field, the rate from the stamps.
  io::series_options o;
  auto s = io::read_series_columns(path + ":/imu/data", o,
                                   {"gyro_z_rad_s", "linear_acceleration.x", "2"});
  ASSERT_TRUE(s) << s.err().message;
  ASSERT_EQ(s->size(), 3U);
  EXPECT_NEAR((*s)[0].tau0_s(), 0.005, 1e-15);
  EXPECT_EQ((*s)[0].topic(), "/imu/data");
  EXPECT_EQ((*s)[0].values()[999], truth(999).gyro_rad_s[2]);
  EXPECT_EQ((*s)[1].values()[500], truth(500).accel_m_s2[0]);
  EXPECT_EQ((*s)[2].values()[3], truth(3).gyro_rad_s[1]);
  // The topic option, and the bag compressed.
  o.topic = "/imu/data";
  o.column = "accel_z_m_s2";
  for (const char* ext : {"", ".gz", ".xz", ".zst"}) {
    std::string p = path;
    if (*ext != '\0') {
      p += ext;
      write_compressed(p, read_bytes(path));
    }
    auto one = io::read_series(p, o);
    ASSERT_TRUE(one) << ext << ": " << one.err().message;
    EXPECT_EQ(one->values()[777], truth(777).accel_m_s2[2]) << ext;
  }
}

TEST_P(Bags, TheOnlyImuTopicIsTakenAndOtherwiseNamed) {
  const std::string one = name("one");
  auto topics = three_topics(50);
  write(one, {topics[0], topics[2]});
  auto t = io::read_imu_bag(one, "");
  ASSERT_TRUE(t) << t.err().message;
  EXPECT_EQ(t->topic, "/imu/data");
  const std::string two = name("two");
  write(two, topics);
  t = io::read_imu_bag(two, "");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find("2 IMU topics (/imu/data, /imu/raw)"), std::string::npos)
      << t.err().message;
  t = io::read_imu_bag(two, "/status");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find("topic /status holds std_msgs/UInt32"), std::string::npos)
      << t.err().message;
  t = io::read_imu_bag(two, "/imu");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find("no topic /imu in the bag; its IMU topics: /imu/data, /imu/raw"),
            std::string::npos)
      << t.err().message;
  t = io::read_imu_bag(two, "/imu/raw");
  ASSERT_TRUE(t) << t.err().message;
  EXPECT_EQ(t->time_s.size(), 5U);
  EXPECT_EQ(t->values[0][4], 7.0);
  // FILE:/a with the topic option /b.
  io::series_options o;
  o.topic = "/imu/raw";
  o.column = "gyro_x_rad_s";
  auto s = io::read_series(two + ":/imu/data", o);
  ASSERT_FALSE(s);
  EXPECT_NE(s.err().message.find("give it once"), std::string::npos) << s.err().message;
}

TEST_P(Bags, AWrongColumnGetsTheNearestName) {
  const std::string path = name("a");
  write(path, three_topics(20));
  io::series_options o;
  o.topic = "/imu/data";
  o.column = "gyro_x";
  auto s = io::read_series(path, o);
  ASSERT_FALSE(s);
  EXPECT_NE(s.err().message.find("did you mean 'gyro_x_rad_s'?"), std::string::npos)
      << s.err().message;
  EXPECT_NE(s.err().message.find("accel_z_m_s2"), std::string::npos) << s.err().message;
  EXPECT_EQ(io::numeric_columns(path, o)->size(), 6U);
}

TEST_P(Bags, GapsAreFoundAndFilledOrSplit) {
  const std::string path = name("gaps");
  // 3 messages lost out of 1000 (0.3 %): at 200, 201 and 700.
  write(path, three_topics(1000, {200, 201, 700}));
  io::series_options o;
  o.topic = "/imu/data";
  o.column = "gyro_x_rad_s";
  auto s = io::read_series(path, o);
  ASSERT_FALSE(s);
  // Named by the first message after the gap (message 201: the 200 before it are 0..199).
  EXPECT_NE(s.err().message.find("message 201 on /imu/data: the time stamps have 2 gaps"),
            std::string::npos)
      << s.err().message;
  o.gaps = io::gap_policy::fill;
  s = io::read_series(path, o);
  ASSERT_TRUE(s) << s.err().message;
  ASSERT_EQ(s->values().size(), 1000U);
  EXPECT_NEAR(s->tau0_s(), 0.005, 1e-15);
  for (std::size_t k = 0; k < 1000; ++k) {
    if (k == 200 || k == 201 || k == 700) continue;
    ASSERT_EQ(s->values()[k], truth(k).gyro_rad_s[0]) << k;
  }
  // Bridged on the straight line between the neighbours.
  const double a = truth(199).gyro_rad_s[0], b = truth(202).gyro_rad_s[0];
  EXPECT_DOUBLE_EQ(s->values()[200], a + (b - a) / 3.0);
  EXPECT_DOUBLE_EQ(s->values()[201], a + 2.0 * (b - a) / 3.0);
  EXPECT_DOUBLE_EQ(s->values()[700], 0.5 * (truth(699).gyro_rad_s[0] + truth(701).gyro_rad_s[0]));
  bool noted = false;
  for (const auto& n : s->notes()) noted |= n.find("3 samples (0.3 % of 1000) bridged") != n.npos;
  EXPECT_TRUE(noted) << fmt::format("{}", fmt::join(s->notes(), " | "));
  o.gaps = io::gap_policy::split;
  s = io::read_series(path, o);
  ASSERT_TRUE(s) << s.err().message;
  EXPECT_EQ(s->values().size(), 498U);  // messages 202..699
  // More than 1 % missing is not bridged.
  std::vector<std::size_t> many;
  for (std::size_t k = 100; k < 112; ++k) many.push_back(k);
  write(path, three_topics(1000, many));
  o.gaps = io::gap_policy::fill;
  s = io::read_series(path, o);
  ASSERT_FALSE(s);
  EXPECT_NE(s.err().message.find("more than 1 % is not bridged"), std::string::npos)
      << s.err().message;
}

TEST_P(Bags, BadMessagesAreErrorsNamingTheMessage) {
  const std::string path = name("bad");
  auto topics = three_topics(100);
  topics[0].messages[42].accel_m_s2[1] = std::nan("");
  write(path, topics);
  auto t = io::read_imu_bag(path, "/imu/data");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find(path), std::string::npos) << t.err().message;
  EXPECT_NE(t.err().message.find("message 43 on /imu/data"), std::string::npos) << t.err().message;
  EXPECT_NE(t.err().message.find("linear_acceleration.y"), std::string::npos) << t.err().message;
  topics = three_topics(100);
  topics[0].messages[60].sec = topics[0].messages[59].sec;  // a stamp repeated
  topics[0].messages[60].nsec = topics[0].messages[59].nsec;
  write(path, topics);
  t = io::read_imu_bag(path, "/imu/data");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find("message 61 on /imu/data"), std::string::npos) << t.err().message;
  EXPECT_NE(t.err().message.find("does not increase"), std::string::npos) << t.err().message;
}

INSTANTIATE_TEST_SUITE_P(Formats, Bags,
                         ::testing::Values(bag_kind{"ros1", false, false},
                                           bag_kind{"ros2", true, false},
                                           bag_kind{"ros2_big_endian", true, true}),
                         [](const auto& p) { return std::string(p.param.name); });

TEST(Ros1Bag, DamagedFilesAreErrorsNamingTheRecord) {
  temp_dir d;
  const std::string path = d.file("a.bag");
  write_ros1_bag(path, three_topics(100));
  const std::string bytes = read_bytes(path);
  const std::string cut = d.file("cut.bag");
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
  auto t = io::read_imu_bag(cut, "/imu/data");
  ASSERT_FALSE(t);
  // The chunk, after the magic (13 bytes) and the bag header record (4 + 69 + 4 + 4096 bytes).
  EXPECT_NE(t.err().message.find(cut + ": record at byte 4186"), std::string::npos)
      << t.err().message;
  EXPECT_NE(t.err().message.find("truncated"), std::string::npos) << t.err().message;
  write_ros1_bag(d.file("bz2.bag"), three_topics(10), "bz2");
  t = io::read_imu_bag(d.file("bz2.bag"), "");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find("rosbag decompress"), std::string::npos) << t.err().message;
  std::ofstream(d.file("v1.bag")) << "#ROSBAG V1.2\n";
  t = io::read_imu_bag(d.file("v1.bag"), "");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find("another version than 2.0"), std::string::npos) << t.err().message;
  t = io::read_imu_bag(d.file("missing.bag"), "");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find("missing.bag"), std::string::npos) << t.err().message;
}

TEST(Ros2Bag, NotABagIsAnError) {
  temp_dir d;
  std::ofstream(d.file("a.db3")) << "time_s,x\n0,1\n";
  auto t = io::read_imu_bag(d.file("a.db3"), "");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find("not a ROS 2 bag"), std::string::npos) << t.err().message;
  t = io::read_imu_bag(d.file("none.db3"), "");
  ASSERT_FALSE(t);
  EXPECT_NE(t.err().message.find("none.db3"), std::string::npos) << t.err().message;
  EXPECT_FALSE(std::ifstream(d.file("none.db3")).good());  // not created by reading
}

}  // namespace
}  // namespace gyroflip::test
