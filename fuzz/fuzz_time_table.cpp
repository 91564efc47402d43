/// \file
/// \brief libFuzzer target: the time-table reader (io::read_time_table, `simulate --temp-profile
/// FILE.csv`) on any bytes, and the profile built from what it accepts.
#include "fuzz_input_file.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/rig/profiles.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const gyroflip::fuzz::input_file f(data, size, ".csv");
  auto t = gyroflip::io::read_time_table(f.path(), "temp_c");
  if (!t) return 0;
  auto p = gyroflip::rig::profile::table(t->time_s, t->value);
  if (p) (void)p->at(t->time_s.front() + 0.5);
  return 0;
}
