/// \file
/// \brief Writers of small ROS bags and compressed files for the readers' tests, written from
/// the formats' specifications, not by the code under test: ROS 1 bag format 2.0
/// (wiki.ros.org/Bags/Format/2.0, records as rosbag's bag.py writes them: a bag header record, one
/// uncompressed chunk with its connection and message records, then the connection records again
/// and a chunk info record) and ROS 2 rosbag2's sqlite3 storage (the `topics` and `messages`
/// tables of rosbag2_storage_default_plugins' sqlite_storage.cpp, messages CDR-encoded as
/// Fast-CDR writes them: encapsulation 00 01, fields aligned to their size from after it).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace gyroflip::test {

/// One sensor_msgs/Imu message: header stamp and the values it carries.
struct imu_msg {
  std::uint32_t sec = 0, nsec = 0;
  std::array<double, 3> gyro_rad_s{}, accel_m_s2{};
};

/// A topic of a bag: its name, its type ("sensor_msgs/Imu" or another) and its messages.
struct bag_topic {
  std::string name;
  std::string type = "sensor_msgs/Imu";
  std::vector<imu_msg> messages;
  std::string frame_id = "imu_link";
};

/// A ROS 1 bag 2.0 file of these topics (messages interleaved by stamp); `chunk_compression`
/// other than "none" only labels the chunk (for the reader's refusal).
void write_ros1_bag(const std::string& path, const std::vector<bag_topic>& topics,
                    const std::string& chunk_compression = "none");

/// A ROS 2 .db3 bag of these topics (type names as ROS 2 spells them: sensor_msgs/msg/Imu);
/// `big_endian` writes CDR big-endian (encapsulation 00 00).
void write_ros2_bag(const std::string& path, const std::vector<bag_topic>& topics,
                    bool big_endian = false);

/// `bytes` compressed as `path`'s extension says (.gz by zlib's gzip writer, .xz by liblzma at
/// preset 1, .zst by libzstd at level 3 with its content checksum, as the zstd program writes) and
/// written there.
void write_compressed(const std::string& path, const std::string& bytes);

/// The whole file as bytes.
[[nodiscard]] std::string read_bytes(const std::string& path);

}  // namespace gyroflip::test
