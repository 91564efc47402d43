/// \file
/// \brief libFuzzer target: the series reader for .npy input (io::read_series), then the phase
/// source over what it read (it checks every sample), on any bytes.
#include "fuzz_input_file.hpp"
#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/io/series.hpp"

#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const gyroflip::fuzz::input_file f(data, size, ".npy");
  gyroflip::io::series_options o;
  if (std::string_view(".npy") != ".csv") o.sample_rate_hz = 100.0;
  auto s = gyroflip::io::read_series(f.path(), o);
  if (!s) return 0;
  for (const auto kind :
       {gyroflip::analysis::input_kind::rate, gyroflip::analysis::input_kind::angle})
    (void)gyroflip::analysis::phase_source::make(s->samples(), kind, s->tau0_s());
  return 0;
}
