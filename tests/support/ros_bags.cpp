/// \file
/// \brief ROS 1 and ROS 2 bag writers and compressed files for tests (see ros_bags.hpp).
#include "support/ros_bags.hpp"

#include <lzma.h>
#include <sqlite3.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace gyroflip::test {

namespace {

void put32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFFU);
}

void put64(std::string& s, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFFU);
}

void putf64(std::string& s, double x, bool big = false) {
  const auto v = std::bit_cast<std::uint64_t>(x);
  for (int i = 0; i < 8; ++i) s += static_cast<char>((v >> (8 * (big ? 7 - i : i))) & 0xFFU);
}

// A header field: 4-byte length, then name=value.
std::string field(const std::string& name, const std::string& value) {
  std::string f;
  put32(f, static_cast<std::uint32_t>(name.size() + 1 + value.size()));
  return f + name + "=" + value;
}

std::string u32_bytes(std::uint32_t v) {
  std::string s;
  put32(s, v);
  return s;
}

// A record: 4-byte header length, header, 4-byte data length, data.
std::string record(const std::string& header, const std::string& data) {
  std::string r;
  put32(r, static_cast<std::uint32_t>(header.size()));
  r += header;
  put32(r, static_cast<std::uint32_t>(data.size()));
  return r + data;
}

// The 37 float64 after the header: orientation (0,0,0,1), covariances 0, the two vectors.
std::vector<double> imu_doubles(const imu_msg& m) {
  std::vector<double> d(37, 0.0);
  d[3] = 1.0;
  for (std::size_t i = 0; i < 3; ++i) {
    d[13 + i] = m.gyro_rad_s[i];
    d[25 + i] = m.accel_m_s2[i];
  }
  return d;
}

struct stamped {
  std::uint64_t ns;
  std::size_t topic;
  const imu_msg* msg;
};

std::vector<stamped> interleaved(const std::vector<bag_topic>& topics) {
  std::vector<stamped> all;
  for (std::size_t t = 0; t < topics.size(); ++t)
    for (const auto& m : topics[t].messages)
      all.push_back({std::uint64_t{m.sec} * 1000000000 + m.nsec, t, &m});
  std::stable_sort(all.begin(), all.end(),
                   [](const stamped& a, const stamped& b) { return a.ns < b.ns; });
  return all;
}

}  // namespace

void write_ros1_bag(const std::string& path, const std::vector<bag_topic>& topics,
                    const std::string& chunk_compression) {
  const auto connection = [&](std::size_t t) {
    const auto& tp = topics[t];
    const bool imu = tp.type == "sensor_msgs/Imu";
    const std::string data = field("topic", tp.name) + field("type", tp.type) +
                             field("md5sum", imu ? "6a62c6daae103f4ff57a132d6f95cec2"
                                                 : "992ce8a1687cec8c8bd883ec73ca41d1") +
                             field("message_definition", "# test");
    return record(field("op", "\x07") + field("conn", u32_bytes(static_cast<std::uint32_t>(t))) +
                      field("topic", tp.name),
                  data);
  };
  std::string chunk;
  for (std::size_t t = 0; t < topics.size(); ++t) chunk += connection(t);
  std::uint32_t seq = 0;
  for (const auto& s : interleaved(topics)) {
    const auto& tp = topics[s.topic];
    std::string body;
    if (tp.type == "sensor_msgs/Imu") {
      put32(body, seq++);
      put32(body, s.msg->sec);
      put32(body, s.msg->nsec);
      put32(body, static_cast<std::uint32_t>(tp.frame_id.size()));
      body += tp.frame_id;
      for (const double x : imu_doubles(*s.msg)) putf64(body, x);
    } else {
      body = u32_bytes(7);  // a std_msgs/UInt32-like payload
    }
    std::string time;
    put32(time, s.msg->sec);
    put32(time, s.msg->nsec);
    chunk +=
        record(field("op", "\x02") + field("conn", u32_bytes(static_cast<std::uint32_t>(s.topic))) +
                   field("time", time),
               body);
  }
  std::string out = "#ROSBAG V2.0\n";
  // Bag header record, its data padded to 4096 bytes as rosbag writes it (index position not
  // used by the reader under test: 0).
  std::string idx;
  put64(idx, 0);
  out += record(field("op", "\x03") + field("index_pos", idx) +
                    field("conn_count", u32_bytes(static_cast<std::uint32_t>(topics.size()))) +
                    field("chunk_count", u32_bytes(1)),
                std::string(4096, ' '));
  out += record(field("op", "\x05") + field("compression", chunk_compression) +
                    field("size", u32_bytes(static_cast<std::uint32_t>(chunk.size()))),
                chunk);
  for (std::size_t t = 0; t < topics.size(); ++t) out += connection(t);
  std::string ver;
  put32(ver, 1);
  out += record(field("op", "\x06") + field("ver", ver), std::string());
  std::ofstream(path, std::ios::binary) << out;
}

void write_ros2_bag(const std::string& path, const std::vector<bag_topic>& topics,
                    bool big_endian) {
  std::remove(path.c_str());
  sqlite3* db = nullptr;
  if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) throw std::runtime_error("sqlite open");
  const auto exec = [&](const std::string& sql) {
    if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr) != SQLITE_OK)
      throw std::runtime_error(sqlite3_errmsg(db));
  };
  // rosbag2 (Humble): sqlite_storage.cpp's schema.
  exec(
      "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY,ros_distro TEXT NOT NULL);"
      "INSERT INTO schema VALUES(3,'humble');"
      "CREATE TABLE metadata(id INTEGER PRIMARY KEY,metadata_version INTEGER NOT NULL,metadata "
      "TEXT NOT NULL);"
      "CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT NULL,type TEXT NOT NULL,"
      "serialization_format TEXT NOT NULL,offered_qos_profiles TEXT NOT NULL);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp INTEGER "
      "NOT NULL, data BLOB NOT NULL);"
      "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
      "BEGIN;");
  for (std::size_t t = 0; t < topics.size(); ++t) {
    std::string type = topics[t].type;
    if (type == "sensor_msgs/Imu") type = "sensor_msgs/msg/Imu";
    exec("INSERT INTO topics VALUES(" + std::to_string(t + 1) + ",'" + topics[t].name + "','" +
         type + "','cdr','')");
  }
  sqlite3_stmt* ins = nullptr;
  sqlite3_prepare_v2(db, "INSERT INTO messages(topic_id,timestamp,data) VALUES(?,?,?)", -1, &ins,
                     nullptr);
  for (const auto& s : interleaved(topics)) {
    const auto& tp = topics[s.topic];
    std::string b;
    const auto u32 = [&](std::uint32_t v) {
      for (int i = 0; i < 4; ++i)
        b += static_cast<char>((v >> (8 * (big_endian ? 3 - i : i))) & 0xFFU);
    };
    b += '\0';
    b += big_endian ? '\0' : '\x01';
    b += std::string(2, '\0');
    if (tp.type == "sensor_msgs/Imu") {
      u32(s.msg->sec);
      u32(s.msg->nsec);
      u32(static_cast<std::uint32_t>(tp.frame_id.size() + 1));
      b += tp.frame_id;
      b += '\0';
      while ((b.size() - 4) % 8 != 0) b += '\0';
      for (const double x : imu_doubles(*s.msg)) putf64(b, x, big_endian);
    } else {
      u32(7);
    }
    sqlite3_bind_int64(ins, 1, static_cast<sqlite3_int64>(s.topic + 1));
    // The receive time, 1 ms after the stamp.
    sqlite3_bind_int64(ins, 2, static_cast<sqlite3_int64>(s.ns + 1000000));
    sqlite3_bind_blob(ins, 3, b.data(), static_cast<int>(b.size()), SQLITE_TRANSIENT);
    if (sqlite3_step(ins) != SQLITE_DONE) throw std::runtime_error(sqlite3_errmsg(db));
    sqlite3_reset(ins);
  }
  sqlite3_finalize(ins);
  exec("COMMIT;");
  sqlite3_close(db);
}

void write_compressed(const std::string& path, const std::string& bytes) {
  std::string out;
  if (path.ends_with(".gz")) {
    gzFile f = gzopen(path.c_str(), "wb");
    if (f == nullptr) throw std::runtime_error("gzopen");
    gzwrite(f, bytes.data(), static_cast<unsigned>(bytes.size()));
    gzclose(f);
    return;
  }
  if (path.ends_with(".xz")) {
    out.resize(lzma_stream_buffer_bound(bytes.size()));
    std::size_t n = 0;
    if (lzma_easy_buffer_encode(
            1, LZMA_CHECK_CRC64, nullptr, reinterpret_cast<const std::uint8_t*>(bytes.data()),
            bytes.size(), reinterpret_cast<std::uint8_t*>(out.data()), &n, out.size()) != LZMA_OK)
      throw std::runtime_error("lzma");
    out.resize(n);
  } else if (path.ends_with(".zst")) {
    // With the content checksum, as the zstd program writes by default.
    out.resize(ZSTD_compressBound(bytes.size()));
    ZSTD_CCtx* c = ZSTD_createCCtx();
    ZSTD_CCtx_setParameter(c, ZSTD_c_compressionLevel, 3);
    ZSTD_CCtx_setParameter(c, ZSTD_c_checksumFlag, 1);
    const std::size_t n = ZSTD_compress2(c, out.data(), out.size(), bytes.data(), bytes.size());
    ZSTD_freeCCtx(c);
    if (ZSTD_isError(n) != 0U) throw std::runtime_error("zstd");
    out.resize(n);
  } else {
    throw std::runtime_error("not a compressed name: " + path);
  }
  std::ofstream(path, std::ios::binary) << out;
}

std::string read_bytes(const std::string& path) {
  std::string out;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return out;
  char buf[1 << 16];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
  std::fclose(f);
  return out;
}

}  // namespace gyroflip::test
