/// \file
/// \brief ROS 1 bag 2.0 and ROS 2 SQLite bags: sensor_msgs/Imu messages (see ros_bag.hpp).
///
/// ROS 1: the bag format 2.0 (wiki.ros.org/Bags/Format/2.0) read directly, without Debian's
/// librosbag-storage-dev, which brings Boost and 62 packages (190 MB) for what is a simple record
/// format (FACTS §10). ROS 2: rosbag2's sqlite3 storage plugin's tables `topics`
/// and `messages` read through SQLite, each message CDR-encoded (OMG DDS-XTypes 1.3, 7.4.3:
/// XCDR1 with the 4-byte encapsulation header of the RTPS 2.5 spec, 10.2; FACTS §10).
#include "gyroflip/io/ros_bag.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/io/compressed.hpp"
#include "gyroflip/io/mapped_file.hpp"

namespace gyroflip::io {

namespace {

// A whole bag decompressed in memory may not exceed this (a decompression bomb is an error).
constexpr std::size_t max_bag_bytes = std::size_t{1} << 36;

// sensor_msgs/Imu after its header, in both encodings: orientation (4 float64), its covariance
// (9), angular_velocity (3), its covariance (9), linear_acceleration (3), its covariance (9).
constexpr std::size_t imu_doubles = 37;
constexpr std::size_t angular_velocity_at = 13;
constexpr std::size_t linear_acceleration_at = 25;

std::uint32_t le32(const char* p) noexcept {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | std::uint32_t{static_cast<unsigned char>(p[i])};
  return v;
}

std::uint32_t be32(const char* p) noexcept {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v = (v << 8) | std::uint32_t{static_cast<unsigned char>(p[i])};
  return v;
}

double f64(const char* p, bool little) noexcept {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) {
    const int at = little ? 7 - i : i;
    v = (v << 8) | std::uint64_t{static_cast<unsigned char>(p[at])};
  }
  return std::bit_cast<double>(v);
}

// One decoded message: header stamp in ns and the six values.
struct imu_message {
  std::int64_t stamp_ns = 0;
  std::array<double, 6> v{};
};

// The six values from the 37 doubles at `p`.
void take_values(const char* p, bool little, imu_message& m) noexcept {
  for (std::size_t i = 0; i < 3; ++i) {
    m.v[i] = f64(p + 8 * (angular_velocity_at + i), little);
    m.v[3 + i] = f64(p + 8 * (linear_acceleration_at + i), little);
  }
}

// Appends message `m` to `t` (stamps strictly increasing, values finite and within
// max_input_magnitude); `where` names the message in errors.
status append(imu_table& t, std::int64_t& first_ns, const imu_message& m, const std::string& path,
              const std::string& where) {
  for (std::size_t c = 0; c < 6; ++c)
    if (!std::isfinite(m.v[c]) || std::abs(m.v[c]) > max_input_magnitude)
      return input_error({path}, fmt::format("{}: {} is {} (not a finite number within {:g})",
                                             where, imu_fields[c], m.v[c], max_input_magnitude));
  if (t.time_s.empty()) first_ns = m.stamp_ns;
  const double ts = static_cast<double>(m.stamp_ns - first_ns) * 1e-9;
  if (!t.time_s.empty() && !(ts > t.time_s.back()))
    return input_error(
        {path},
        fmt::format("{}: its header stamp {}.{:09} s does not increase (the previous "
                    "message's is {:.9f} s later than the first): the driver stamps "
                    "messages out of order or not at all",
                    where, m.stamp_ns / 1000000000, m.stamp_ns % 1000000000, t.time_s.back()));
  t.time_s.push_back(ts);
  for (std::size_t c = 0; c < 6; ++c) t.values[c].push_back(m.v[c]);
  return ok();
}

// The IMU topic asked for among `imu_topics` (all of type sensor_msgs/Imu), or the only one.
// `others`: the bag's other topics with their types, for the message.
result<std::string> choose_topic(const std::string& path, const std::string& topic,
                                 const std::vector<std::string>& imu_topics,
                                 const std::vector<std::pair<std::string, std::string>>& others) {
  const auto list = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& n : v) s += (s.empty() ? "" : ", ") + printable(n, 100);
    return s;
  };
  if (!topic.empty()) {
    if (std::find(imu_topics.begin(), imu_topics.end(), topic) != imu_topics.end()) return topic;
    for (const auto& [name, type] : others)
      if (name == topic)
        return about_parameter(
            input_error(
                {path},
                fmt::format("topic {} holds {}, not sensor_msgs/Imu{}", printable(topic, 100),
                            printable(type, 100),
                            imu_topics.empty() ? "" : "; its IMU topics: " + list(imu_topics))),
            "topic");
    return about_parameter(
        input_error({path},
                    fmt::format("no topic {} in the bag; {}", printable(topic, 100),
                                imu_topics.empty() ? "it has no sensor_msgs/Imu topic"
                                                   : "its IMU topics: " + list(imu_topics))),
        "topic");
  }
  if (imu_topics.size() == 1) return imu_topics.front();
  if (imu_topics.empty()) {
    std::string all;
    for (const auto& [name, type] : others)
      all += (all.empty() ? "" : ", ") + printable(name, 100) + " (" + printable(type, 100) + ")";
    return input_error({path}, fmt::format("no sensor_msgs/Imu topic in the bag (its topics: {})",
                                           all.empty() ? "none" : all));
  }
  return about_parameter(
      input_error({path}, fmt::format("{} IMU topics ({}): name one (FILE:/topic, or the topic "
                                      "option)",
                                      imu_topics.size(), list(imu_topics))),
      "topic");
}

// ---- ROS 1: bag format 2.0 ----

constexpr std::string_view bag_magic = "#ROSBAG V2.0\n";
constexpr std::string_view ros1_imu_type = "sensor_msgs/Imu";
// The MD5 of sensor_msgs/Imu's definition (rosmsg md5 sensor_msgs/Imu): another definition under
// the same name would be decoded wrongly.
constexpr std::string_view ros1_imu_md5 = "6a62c6daae103f4ff57a132d6f95cec2";

enum : unsigned char {
  op_message = 0x02,
  op_bag_header = 0x03,
  op_index = 0x04,
  op_chunk = 0x05,
  op_chunk_info = 0x06,
  op_connection = 0x07
};

// A record's header fields (`name=value`, each after its 4-byte length).
struct fields {
  std::map<std::string, std::string_view, std::less<>> f;
  [[nodiscard]] std::optional<std::string_view> get(std::string_view name) const {
    const auto it = f.find(name);
    if (it == f.end()) return std::nullopt;
    return it->second;
  }
};

std::optional<fields> parse_fields(std::string_view h) {
  fields out;
  while (!h.empty()) {
    if (h.size() < 4) return std::nullopt;
    const std::uint32_t len = le32(h.data());
    h.remove_prefix(4);
    if (len > h.size()) return std::nullopt;
    const std::string_view field = h.substr(0, len);
    h.remove_prefix(len);
    const auto eq = field.find('=');
    if (eq == std::string_view::npos) return std::nullopt;
    out.f[std::string(field.substr(0, eq))] = field.substr(eq + 1);
  }
  return out;
}

struct ros1_connection {
  std::string topic, type, md5;
};

struct ros1_message {
  std::uint32_t conn = 0;
  std::size_t offset = 0;  // of its record in the file
  std::string_view data;
};

class ros1_reader {
 public:
  ros1_reader(const std::string& path, std::string_view file) : path_(path), file_(file) {}

  // Every record of `d` (the file after its magic, or a chunk's records), at file offset `base`
  // when `in_file` (a chunk's data are views of the file when uncompressed).
  status walk(std::string_view d, bool top) {
    while (!d.empty()) {
      const std::size_t at = offset_of(d.data());
      if (d.size() < 4) return bad(at, "a record is cut short (truncated file?)");
      const std::uint32_t hlen = le32(d.data());
      if (hlen > d.size() - 4) return bad(at, "its header runs past the end (truncated file?)");
      const std::string_view header = d.substr(4, hlen);
      d.remove_prefix(4 + std::size_t{hlen});
      if (d.size() < 4) return bad(at, "its data length is missing (truncated file?)");
      const std::uint32_t dlen = le32(d.data());
      if (dlen > d.size() - 4) return bad(at, "its data run past the end (truncated file?)");
      const std::string_view data = d.substr(4, dlen);
      d.remove_prefix(4 + std::size_t{dlen});
      const auto h = parse_fields(header);
      if (!h) return bad(at, "its header fields are malformed");
      const auto op = h->get("op");
      if (!op || op->size() != 1) return bad(at, "its header has no op field");
      const auto code = static_cast<unsigned char>((*op)[0]);
      if (code == op_connection) {
        const auto conn = h->get("conn");
        const auto topic = h->get("topic");
        const auto c = parse_fields(data);
        if (!conn || conn->size() != 4 || !topic || !c)
          return bad(at, "a connection record without its conn, topic or fields");
        ros1_connection rc{std::string(*topic), std::string(c->get("type").value_or("")),
                           std::string(c->get("md5sum").value_or(""))};
        connections_[le32(conn->data())] = rc;
      } else if (code == op_message) {
        const auto conn = h->get("conn");
        if (!conn || conn->size() != 4) return bad(at, "a message record without its conn");
        messages_.push_back({le32(conn->data()), at, data});
      } else if (code == op_chunk) {
        if (!top) return bad(at, "a chunk inside a chunk");
        const auto comp = h->get("compression");
        if (!comp) return bad(at, "a chunk without its compression field");
        if (*comp != "none")
          return bad(at, fmt::format("a chunk compressed with {}: not read here; decompress the "
                                     "bag first (rosbag decompress FILE.bag)",
                                     printable(*comp, 20)));
        if (auto s = walk(data, false); !s) return s;
      } else if (code == op_bag_header || code == op_index || code == op_chunk_info) {
        // Indexes: the records themselves are read in order.
      } else {
        return bad(at, fmt::format("unknown record op 0x{:02x}", code));
      }
    }
    return ok();
  }

  result<imu_table> imu(const std::string& topic) {
    std::vector<std::string> imu_topics;
    std::vector<std::pair<std::string, std::string>> others;
    for (const auto& [id, c] : connections_) {
      if (c.type == ros1_imu_type) {
        if (std::find(imu_topics.begin(), imu_topics.end(), c.topic) == imu_topics.end())
          imu_topics.push_back(c.topic);
      } else {
        others.emplace_back(c.topic, c.type);
      }
    }
    auto chosen = choose_topic(path_, topic, imu_topics, others);
    if (!chosen) return chosen.err();
    for (const auto& [id, c] : connections_)
      if (c.topic == *chosen && c.md5 != ros1_imu_md5)
        return input_error(
            {path_}, fmt::format("topic {}: sensor_msgs/Imu of MD5 {}, not the standard "
                                 "definition's {}: another message layout",
                                 printable(*chosen, 100), printable(c.md5, 40), ros1_imu_md5));
    imu_table t;
    t.topic = *chosen;
    std::int64_t first_ns = 0;
    std::size_t k = 0;
    for (const auto& m : messages_) {
      const auto it = connections_.find(m.conn);
      if (it == connections_.end())
        return bad(m.offset, fmt::format("a message on connection {}, which no connection "
                                         "record defines",
                                         m.conn));
      if (it->second.topic != *chosen) continue;
      ++k;
      const std::string where =
          fmt::format("message {} on {} (record at byte {})", k, printable(*chosen, 100), m.offset);
      // Header: seq (uint32), stamp (uint32 sec, uint32 nsec), frame_id (uint32 length, bytes).
      const std::string_view d = m.data;
      if (d.size() < 16) return input_error({path_}, where + ": too short for a sensor_msgs/Imu");
      const std::uint32_t frame_len = le32(d.data() + 12);
      if (frame_len > d.size() - 16 || d.size() - 16 - frame_len != 8 * imu_doubles)
        return input_error({path_}, fmt::format("{}: {} bytes, not a sensor_msgs/Imu (its frame_id "
                                                "announces {} bytes)",
                                                where, d.size(), frame_len));
      imu_message msg;
      msg.stamp_ns = std::int64_t{le32(d.data() + 4)} * 1000000000 + le32(d.data() + 8);
      take_values(d.data() + 16 + frame_len, true, msg);
      if (auto s = append(t, first_ns, msg, path_, where); !s) return s.err();
    }
    return t;
  }

 private:
  [[nodiscard]] std::size_t offset_of(const char* p) const noexcept {
    return static_cast<std::size_t>(p - file_.data());
  }
  [[nodiscard]] error bad(std::size_t at, std::string_view what) const {
    return input_error({path_}, fmt::format("record at byte {}: {}", at, what));
  }
  const std::string& path_;
  std::string_view file_;
  std::map<std::uint32_t, ros1_connection> connections_;
  std::vector<ros1_message> messages_;
};

result<imu_table> read_ros1(const std::string& path, std::string_view file,
                            const std::string& topic) {
  if (!file.starts_with(bag_magic))
    return input_error({path}, file.starts_with("#ROSBAG")
                                   ? "a ROS bag of another version than 2.0 (the first line is "
                                     "not #ROSBAG V2.0; rosbag reindex or migrate it)"
                                   : "not a ROS 1 bag (its first line is not #ROSBAG V2.0)");
  ros1_reader r(path, file);
  if (auto s = r.walk(file.substr(bag_magic.size()), true); !s) return s.err();
  return r.imu(topic);
}

// ---- ROS 2: rosbag2's SQLite storage ----

constexpr std::string_view ros2_imu_type = "sensor_msgs/msg/Imu";

class sqlite_db {
 public:
  sqlite_db() = default;
  sqlite_db(const sqlite_db&) = delete;
  sqlite_db& operator=(const sqlite_db&) = delete;
  sqlite_db(sqlite_db&&) = delete;
  sqlite_db& operator=(sqlite_db&&) = delete;
  ~sqlite_db() { sqlite3_close(db_); }
  sqlite3* db_ = nullptr;
};

class statement {
 public:
  statement(sqlite3* db, const char* sql) { sqlite3_prepare_v2(db, sql, -1, &s_, nullptr); }
  statement(const statement&) = delete;
  statement& operator=(const statement&) = delete;
  statement(statement&&) = delete;
  statement& operator=(statement&&) = delete;
  ~statement() { sqlite3_finalize(s_); }
  sqlite3_stmt* s_ = nullptr;
};

std::string column_text(sqlite3_stmt* s, int i) {
  const auto* p = sqlite3_column_text(s, i);
  return p == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(p));  // NOLINT
}

// One CDR-encoded sensor_msgs/msg/Imu (`d`, with its encapsulation header).
result<imu_message> decode_cdr_imu(std::string_view d, const std::string& path,
                                   const std::string& where) {
  // Encapsulation: 00 00 plain CDR big-endian, 00 01 little-endian; 2 option bytes.
  if (d.size() < 4 || d[0] != 0 || (d[1] != 0 && d[1] != 1))
    return input_error({path}, where +
                                   ": not plain CDR (its encapsulation header is not "
                                   "00 00 or 00 01)");
  const bool little = d[1] == 1;
  const std::string_view b = d.substr(4);  // alignment counts from here
  // Header: stamp (int32 sec, uint32 nanosec), frame_id (uint32 length with its NUL, bytes);
  // then float64s aligned to 8.
  if (b.size() < 12) return input_error({path}, where + ": too short for a sensor_msgs/Imu");
  const auto u32 = [&](std::size_t at) {
    return little ? le32(b.data() + at) : be32(b.data() + at);
  };
  const std::uint32_t frame_len = u32(8);
  if (frame_len > b.size() - 12)
    return input_error({path}, fmt::format("{}: its frame_id announces {} bytes, more than the "
                                           "message holds",
                                           where, frame_len));
  const std::size_t doubles_at = (12 + std::size_t{frame_len} + 7) / 8 * 8;
  if (b.size() < doubles_at || b.size() - doubles_at != 8 * imu_doubles)
    return input_error({path}, fmt::format("{}: {} bytes, not a sensor_msgs/Imu", where, d.size()));
  const std::uint32_t nsec = u32(4);
  if (nsec >= 1000000000)
    return input_error({path},
                       fmt::format("{}: its stamp's nanosec {} is not below 1e9", where, nsec));
  imu_message m;
  m.stamp_ns = std::int64_t{static_cast<std::int32_t>(u32(0))} * 1000000000 + nsec;
  take_values(b.data() + doubles_at, little, m);
  return m;
}

result<imu_table> read_ros2(const std::string& path, const std::vector<char>* image,
                            const std::string& topic) {
  sqlite_db db;
  if (image == nullptr) {
    // Debian's SQLite takes names starting with "file:" as URIs (SQLITE_USE_URI): "./" keeps such
    // a name a file's.
    const std::string name = path.starts_with("file:") ? "./" + path : path;
    if (sqlite3_open_v2(name.c_str(), &db.db_, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX,
                        nullptr) != SQLITE_OK)
      return io_error(path, fmt::format("SQLite cannot open it: {}", sqlite3_errmsg(db.db_)));
  } else {
    // A decompressed bag: SQLite reads the image in memory, read-only (never resized or freed).
    if (sqlite3_open_v2(":memory:", &db.db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOMUTEX,
                        nullptr) != SQLITE_OK ||
        sqlite3_deserialize(
            db.db_, "main",
            reinterpret_cast<unsigned char*>(const_cast<char*>(image->data())),  // NOLINT
            static_cast<sqlite3_int64>(image->size()), static_cast<sqlite3_int64>(image->size()),
            SQLITE_DESERIALIZE_READONLY) != SQLITE_OK)
      return runtime_error(fmt::format("{}: SQLite cannot read the image", path));
  }
  // A damaged file must fail, not be "repaired" by SQLite: defensive, no schema writes.
  sqlite3_db_config(db.db_, SQLITE_DBCONFIG_DEFENSIVE, 1, nullptr);
  const auto sql_error = [&](std::string_view what) {
    return input_error({path},
                       fmt::format("not a ROS 2 bag ({}: {})", what, sqlite3_errmsg(db.db_)));
  };
  std::vector<std::string> imu_topics;
  std::vector<std::pair<std::string, std::string>> others;
  std::map<std::string, std::pair<std::int64_t, std::string>> ids;  // name -> id, format
  {
    statement q(db.db_, "SELECT id, name, type, serialization_format FROM topics ORDER BY id");
    if (q.s_ == nullptr) return sql_error("its topics table");
    while (true) {
      const int rc = sqlite3_step(q.s_);
      if (rc == SQLITE_DONE) break;
      if (rc != SQLITE_ROW) return sql_error("its topics table");
      const std::string name = column_text(q.s_, 1), type = column_text(q.s_, 2);
      ids[name] = {sqlite3_column_int64(q.s_, 0), column_text(q.s_, 3)};
      if (type == ros2_imu_type)
        imu_topics.push_back(name);
      else
        others.emplace_back(name, type);
    }
  }
  auto chosen = choose_topic(path, topic, imu_topics, others);
  if (!chosen) return chosen.err();
  const auto& [topic_id, format] = ids[*chosen];
  if (format != "cdr")
    return input_error({path}, fmt::format("topic {} is serialised as {}, not cdr",
                                           printable(*chosen, 100), printable(format, 40)));
  statement q(db.db_, "SELECT id, data FROM messages WHERE topic_id = ? ORDER BY timestamp, id");
  if (q.s_ == nullptr) return sql_error("its messages table");
  sqlite3_bind_int64(q.s_, 1, topic_id);
  imu_table t;
  t.topic = *chosen;
  std::int64_t first_ns = 0;
  std::size_t k = 0;
  while (true) {
    const int rc = sqlite3_step(q.s_);
    if (rc == SQLITE_DONE) break;
    if (rc != SQLITE_ROW) return sql_error("its messages table");
    ++k;
    const std::string where = fmt::format("message {} on {} (messages row id {})", k,
                                          printable(*chosen, 100), sqlite3_column_int64(q.s_, 0));
    const auto* blob = static_cast<const char*>(sqlite3_column_blob(q.s_, 1));
    const auto size = static_cast<std::size_t>(sqlite3_column_bytes(q.s_, 1));
    auto m = decode_cdr_imu(blob == nullptr ? std::string_view() : std::string_view(blob, size),
                            path, where);
    if (!m) return m.err();
    if (auto s = append(t, first_ns, *m, path, where); !s) return s.err();
  }
  return t;
}

}  // namespace

bool is_ros_bag(std::string_view path) noexcept {
  const std::string_view inner = without_compression(path);
  return inner.ends_with(".bag") || inner.ends_with(".db3");
}

result<imu_table> read_imu_bag(const std::string& path, const std::string& topic) {
  const bool packed = compression_of(path) != compression::none;
  const bool ros2 = without_compression(path).ends_with(".db3");
  std::vector<char> unpacked;
  if (packed) {
    auto u = read_decompressed(path, max_bag_bytes);
    if (!u) return u.err();
    unpacked = std::move(*u);
  }
  result<imu_table> t = runtime_error("unread");
  if (ros2) {
    if (!packed) {
      // SQLite would create an empty database for a missing name: check it exists first.
      auto f = mapped_file::open(path);
      if (!f) return f.err();
      if (f->data().empty()) return input_error({path}, "empty file (expected a ROS 2 bag)");
    }
    t = read_ros2(path, packed ? &unpacked : nullptr, topic);
  } else if (packed) {
    t = read_ros1(path, std::string_view(unpacked.data(), unpacked.size()), topic);
  } else {
    auto f = mapped_file::open(path);
    if (!f) return f.err();
    t = read_ros1(path, f->data(), topic);
  }
  if (!t) return t;
  if (t->time_s.empty())
    return input_error({path}, fmt::format("topic {} has no messages", printable(t->topic, 100)));
  return t;
}

}  // namespace gyroflip::io
