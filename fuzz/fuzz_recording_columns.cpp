/// \file
/// \brief libFuzzer target: a recording's columns held in memory (io::rows_of_columns, the Python
/// module's calibrate/compensate input) on any doubles, then the cycles of what it accepts.
/// Byte 0: bit 0 temp_c given, bit 1 n_avg given, bits 2-7 the angle tolerance (0..6.3 deg);
/// then float64 values, column by column (time, angle, rate[, temp][, n_avg]), the row count
/// being what the bytes allow.
#include <cstdint>
#include <cstring>
#include <vector>

#include "gyroflip/io/recording.hpp"
#include "gyroflip/method/cycles.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool temp = (data[0] & 1U) != 0;
  const bool navg = (data[0] & 2U) != 0;
  const double tol = static_cast<double>(data[0] >> 2U) * 0.1;
  const std::size_t columns = 3U + (temp ? 1U : 0U) + (navg ? 1U : 0U);
  const std::size_t rows = (size - 1) / sizeof(double) / columns;
  std::vector<double> v(rows * columns);
  if (!v.empty()) std::memcpy(v.data(), data + 1, v.size() * sizeof(double));
  const auto col = [&](std::size_t k) {
    return std::span<const double>(v).subspan(k * rows, rows);
  };
  gyroflip::io::recording_columns c{col(0), col(1), col(2), {}, {}};
  if (temp) c.temp_c = col(3);
  if (navg) c.n_avg = col(temp ? 4 : 3);
  const auto r = gyroflip::io::rows_of_columns(c, tol);
  if (!r) return 0;
  (void)gyroflip::method::cycles_of_rows("<arrays>", r->rows, gyroflip::method::pairing::abba, {},
                                         r->positions);
  return 0;
}
