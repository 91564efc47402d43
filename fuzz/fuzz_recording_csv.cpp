/// \file
/// \brief libFuzzer target: the recording reader (io::recording_reader as method::read_cycles reads
/// it, both pairings) on any bytes.
#include "fuzz_input_file.hpp"
#include "gyroflip/io/recording.hpp"
#include "gyroflip/method/cycles.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const gyroflip::fuzz::input_file f(data, size, ".csv");
  for (const auto p : {gyroflip::method::pairing::abba, gyroflip::method::pairing::simple}) {
    auto reader = gyroflip::io::recording_reader::open(f.path());
    if (!reader) return 0;
    (void)gyroflip::method::read_cycles(*reader, p);
  }
  return 0;
}
