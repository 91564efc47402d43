/// \file
/// \brief libFuzzer target: the TOML sensor-preset parser (sensor::parse_toml_preset) on any text,
/// and a gyro built from what it accepts (validated parameters must make a working model).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "gyroflip/sensor/gyro.hpp"
#include "gyroflip/sensor/presets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);  // NOLINT
  const auto p = gyroflip::sensor::parse_toml_preset(text, "fuzz.toml");
  if (!p) return 0;
  auto g = gyroflip::sensor::gyro::make(p->params, 2e-3, 0.0, 1);
  if (!g) std::abort();  // a preset the parser accepts must build
  for (int i = 1; i <= 1000; ++i) (void)g->sample(i * 2e-3, 20.0, 0.0);
  return 0;
}
