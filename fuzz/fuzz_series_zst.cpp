/// \file
/// \brief libFuzzer target: the series reader for .csv.zst input (io::read_series: the decompressor
/// under the CSV reader), then the phase
/// source over what it read, on any bytes.
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return gyroflip::fuzz::fuzz_series(data, size, ".csv.zst");
}
