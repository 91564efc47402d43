/// \file
/// \brief .npy and raw float64 writers for tests (see series_files.hpp).
#include "support/series_files.hpp"

#include <cstdint>
#include <fstream>

namespace gyroflip::test {

void write_npy(const std::string& path, const std::vector<double>& values,
               const std::string& descr) {
  // Header padded with spaces so that magic + length + header is a multiple of 64 bytes.
  std::string header = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (" +
                       std::to_string(values.size()) + ",), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::ofstream f(path, std::ios::binary);
  f.write("\x93NUMPY\x01\x00", 8);
  const auto len = static_cast<std::uint16_t>(header.size());
  f.put(static_cast<char>(len & 0xFF));
  f.put(static_cast<char>(len >> 8));
  f << header;
  f.write(reinterpret_cast<const char*>(values.data()),  // NOLINT: bytes of float64
          static_cast<std::streamsize>(values.size() * sizeof(double)));
}

void write_f64(const std::string& path, const std::vector<double>& values) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(values.data()),  // NOLINT: bytes of float64
          static_cast<std::streamsize>(values.size() * sizeof(double)));
}

}  // namespace gyroflip::test
