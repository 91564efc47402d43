/// \file
/// \brief libFuzzer target: the recording reader (io::read_cycles, both pairings) on any bytes.
#include "fuzz_input_file.hpp"
#include "gyroflip/io/recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const gyroflip::fuzz::input_file f(data, size, ".csv");
  for (const auto p : {gyroflip::method::pairing::abba, gyroflip::method::pairing::simple})
    (void)gyroflip::io::read_cycles(f.path(), p);
  return 0;
}
