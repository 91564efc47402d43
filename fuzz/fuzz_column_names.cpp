/// \file
/// \brief libFuzzer target: what gyroflip reads from a column's name - its sensor and unit
/// (io::unit_of_column) and the "did you mean" of a missing column (io::did_you_mean) - on any
/// bytes (a header field is user text).
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/io/csv.hpp"
#include "gyroflip/io/noise_report.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view name(reinterpret_cast<const char*>(data), size);  // NOLINT: bytes
  if (const auto u = gyroflip::io::unit_of_column(name))
    if (u->quantity != "gyro" && u->quantity != "accel") __builtin_trap();
  // The name against the header it is split into at commas, and against a fixed header.
  std::vector<std::string> header;
  std::size_t from = 0;
  for (std::size_t i = 0; i <= name.size(); ++i)
    if (i == name.size() || name[i] == ',') {
      header.emplace_back(name.substr(from, i - from));
      from = i + 1;
    }
  const std::string near = gyroflip::io::did_you_mean(name.substr(0, name.size() / 2), header);
  bool listed = near.empty();
  for (const auto& h : header) listed |= h == near;
  if (!listed) __builtin_trap();  // a suggestion is always one of the names
  (void)gyroflip::io::did_you_mean(name, {"gyro_x_dps", "time_s", "accel_z_m_s2"});
  return 0;
}
