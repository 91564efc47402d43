/// \file
/// \brief The body shared by the series fuzz targets (fuzz_input_file.hpp).
#include <string>
#include <string_view>

#include "fuzz_input_file.hpp"
#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/io/ros_bag.hpp"
#include "gyroflip/io/series.hpp"

namespace gyroflip::fuzz {

int fuzz_series(const std::uint8_t* data, std::size_t size, const char* ext) {
  const input_file f(data, size, ext);
  io::series_options o;
  // CSV, also compressed (.csv.gz, .csv.xz, .csv.zst); ROS bags take their rate from the stamps.
  const bool csv = std::string_view(ext).starts_with(".csv");
  const bool bag = io::is_ros_bag(ext);
  if (bag) {
    // Named strings, not a conditional of literals (GCC 12's -Wrestrict false positive on it).
    static const std::string accel_z = "linear_acceleration.z", gyro_x = "gyro_x_rad_s";
    static const std::string imu_topic = "/imu/data", any_topic;
    o.column = (size & 1U) != 0 ? accel_z : gyro_x;
    o.gaps = (size & 2U) != 0 ? io::gap_policy::fill : io::gap_policy::split;
    if (auto t = io::read_imu_bag(f.path(), (size & 4U) != 0 ? imu_topic : any_topic))
      (void)t->time_s.size();
  } else if (!csv) {
    o.sample_rate_hz = 100.0;
  }
  // CSV: the dialect and gap options from the input's length, so that every byte stays the
  // file's (and the corpus keeps its meaning): decimal comma, no header, gaps split, ns stamps.
  if (csv) {
    o.dialect.decimal = (size & 1U) != 0 ? ',' : '.';
    o.dialect.header = (size & 2U) == 0;
    if (!o.dialect.header) o.column = std::string("2");  // moved in: GCC 12 -Wrestrict
    o.gaps = (size & 4U) != 0 ? io::gap_policy::split : io::gap_policy::error;
    if ((size & 16U) != 0) o.gaps = io::gap_policy::fill;
    if ((size & 8U) != 0) o.time_unit_s = 1e-9;
    if (auto names = io::numeric_columns(f.path(), o))
      if (auto all = io::read_series_columns(f.path(), o, *names))
        for (const auto& one : *all) (void)one.tau0_s();
  }
  auto s = io::read_series(f.path(), o);
  if (!s) return 0;
  for (const auto kind : {analysis::input_kind::rate, analysis::input_kind::angle})
    (void)analysis::phase_source::make(s->samples(), kind, s->tau0_s());
  return 0;
}

}  // namespace gyroflip::fuzz
