/// \file
/// \brief libFuzzer target: the series reader for .npy input (io::read_series), then the phase
/// source over what it read (it checks every sample), on any bytes.
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return gyroflip::fuzz::fuzz_series(data, size, ".npy");
}
