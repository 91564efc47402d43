/// \file
/// \brief libFuzzer target: the ROS 2 bag reader (io::read_imu_bag, io::read_series on a .db3).
/// As fuzz_series_hdf5 does for libhdf5, it does not feed raw bytes to SQLite's file parser (not
/// gyroflip's code); it builds a rosbag2 database from the input bytes - its topics (names, types,
/// serialisation formats) and their messages' CDR blobs, any bytes - and fuzzes gyroflip's part:
/// the choice of topic, the CDR decoder, the stamps and gap checks.
#include <sqlite3.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/io/ros_bag.hpp"
#include "gyroflip/io/series.hpp"

namespace {

// Input layout: byte 0 the topics (bits 0-1: how many, 1 to 3; bits 2-4: each one's type is
// sensor_msgs/msg/Imu when set; bit 5: the second topic serialised as "json"; bit 6: the topic
// asked for), then messages: a topic byte, a 2-byte little-endian length, that many blob bytes.
int fuzz_db3(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const char* dir = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
  const std::string path =
      std::string(dir) + "/gyroflip-fuzz-" + std::to_string(::getpid()) + ".db3";
  std::remove(path.c_str());
  sqlite3* db = nullptr;
  if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) std::abort();
  sqlite3_exec(db,
               "PRAGMA journal_mode=OFF; CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT "
               "NULL,type TEXT NOT NULL,serialization_format TEXT NOT NULL,offered_qos_profiles "
               "TEXT NOT NULL); CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT "
               "NULL,timestamp INTEGER NOT NULL,data BLOB NOT NULL); BEGIN;",
               nullptr, nullptr, nullptr);
  const unsigned head = data[0];
  const unsigned topics = 1 + (head & 3U) % 3;
  static const char* const names[] = {"/imu/data", "/imu/b", "/other"};
  for (unsigned t = 0; t < topics; ++t) {
    const bool imu = ((head >> (2 + t)) & 1U) != 0;
    const bool json = t == 1 && ((head >> 5) & 1U) != 0;
    const std::string sql = "INSERT INTO topics VALUES(" + std::to_string(t + 1) + ",'" + names[t] +
                            "','" + (imu ? "sensor_msgs/msg/Imu" : "std_msgs/msg/UInt32") + "','" +
                            (json ? "json" : "cdr") + "','')";
    sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr);
  }
  sqlite3_stmt* ins = nullptr;
  sqlite3_prepare_v2(db, "INSERT INTO messages(topic_id,timestamp,data) VALUES(?,?,?)", -1, &ins,
                     nullptr);
  std::size_t p = 1;
  std::int64_t stamp = 0;
  while (p + 3 <= size) {
    const unsigned topic = 1 + data[p] % topics;
    const std::size_t len = std::size_t{data[p + 1]} | (std::size_t{data[p + 2]} << 8);
    p += 3;
    const std::size_t n = len < size - p ? len : size - p;
    sqlite3_bind_int(ins, 1, static_cast<int>(topic));
    sqlite3_bind_int64(ins, 2, stamp += 1000);
    sqlite3_bind_blob(ins, 3, data + p, static_cast<int>(n), SQLITE_TRANSIENT);
    sqlite3_step(ins);
    sqlite3_reset(ins);
    p += n;
  }
  sqlite3_finalize(ins);
  sqlite3_exec(db, "COMMIT;", nullptr, nullptr, nullptr);
  sqlite3_close(db);

  const std::string topic = ((head >> 6) & 1U) != 0 ? "/imu/data" : "";
  if (auto t = gyroflip::io::read_imu_bag(path, topic)) (void)t->time_s.size();
  gyroflip::io::series_options o;
  o.topic = topic;
  o.column = (head & 128U) != 0 ? "accel_y_m_s2" : "gyro_z_rad_s";
  o.gaps = (size & 1U) != 0 ? gyroflip::io::gap_policy::fill : gyroflip::io::gap_policy::split;
  if (auto s = gyroflip::io::read_series(path, o))
    (void)gyroflip::analysis::phase_source::make(s->samples(), gyroflip::analysis::input_kind::rate,
                                                 s->tau0_s());
  std::remove(path.c_str());
  return 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return fuzz_db3(data, size);
}
