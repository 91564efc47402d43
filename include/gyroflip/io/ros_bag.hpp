/// \file
/// \brief The IMU messages of a ROS bag (docs/FORMATS.md, "ROS bags"): ROS 1 `.bag` (format 2.0)
/// and ROS 2 `.db3` (rosbag2's SQLite storage, CDR), `sensor_msgs/Imu` on one topic, as a table of
/// six columns on the messages' header stamps.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::io {

/// The columns of an IMU table, in sensor_msgs/Imu's units (REP 103: rad/s and m/s^2), named so
/// that io::unit_of_column reads their unit.
inline constexpr std::array<std::string_view, 6> imu_columns{
    "gyro_x_rad_s", "gyro_y_rad_s", "gyro_z_rad_s", "accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"};
/// The message fields the columns hold (accepted as column names too).
inline constexpr std::array<std::string_view, 6> imu_fields{
    "angular_velocity.x",    "angular_velocity.y",    "angular_velocity.z",
    "linear_acceleration.x", "linear_acceleration.y", "linear_acceleration.z"};

/// A topic's messages: header stamps (s after the first message's, rebased in integer
/// nanoseconds, so that epoch stamps keep their precision) and the six columns, in the bag's order.
struct imu_table {
  std::string topic;
  std::vector<double> time_s;
  std::array<std::vector<double>, 6> values;
};

/// True for the names read_imu_bag reads: `.bag` and `.db3`, compressed or not.
[[nodiscard]] bool is_ros_bag(std::string_view path) noexcept;

/// Reads topic `topic`'s sensor_msgs/Imu messages from `path` (.bag, .db3, or either compressed:
/// .gz/.xz/.zst, read into memory). An empty `topic` takes the bag's only IMU topic. Errors name
/// the file and the record (ROS 1: its byte offset; ROS 2: the message's row id): not a bag, an
/// unsupported chunk compression, a topic that is absent or of another type (listing the IMU
/// topics there are), a message too short for an Imu, a value that is not finite, stamps that do
/// not increase.
[[nodiscard]] result<imu_table> read_imu_bag(const std::string& path, const std::string& topic);

}  // namespace gyroflip::io
