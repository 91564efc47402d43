/// \file
/// \brief libFuzzer target: the ROS 1 bag reader (io::read_imu_bag) and the series reader for .bag
/// input (io::read_series), then the phase source over what it read, on any bytes.
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return gyroflip::fuzz::fuzz_series(data, size, ".bag");
}
