/// \file
/// \brief The body shared by the series fuzz targets (fuzz_input_file.hpp).
#include <string_view>

#include "fuzz_input_file.hpp"
#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/io/series.hpp"

namespace gyroflip::fuzz {

int fuzz_series(const std::uint8_t* data, std::size_t size, const char* ext) {
  const input_file f(data, size, ext);
  io::series_options o;
  if (std::string_view(ext) != ".csv") o.sample_rate_hz = 100.0;
  auto s = io::read_series(f.path(), o);
  if (!s) return 0;
  for (const auto kind : {analysis::input_kind::rate, analysis::input_kind::angle})
    (void)analysis::phase_source::make(s->samples(), kind, s->tau0_s());
  return 0;
}

}  // namespace gyroflip::fuzz
