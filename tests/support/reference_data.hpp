/// \file
/// \brief Readers for the reference data the analysis tests use (tests/vectors/stable32, the
/// GPS set in ../shared) and the NIST SP1065 1000-point generator.
#pragma once

#include <cstddef>
#include <istream>
#include <optional>
#include <string>
#include <vector>

namespace gyroflip::test {

/// Numbers of a one-column text file, skipping '#' lines.
std::vector<double> read_values(std::istream& in);
std::vector<double> read_values(const std::string& path);

/// One row of a Stable32 result table (README of ../shared/reference/allan).
struct stable32_row {
  std::size_t af = 0;
  std::size_t n = 0;
  int alpha = 0;
  double lo = 0.0, sigma = 0.0, hi = 0.0;
};
std::vector<stable32_row> read_stable32_table(const std::string& path);

/// Folder of the Stable32 GPS tables in ../shared (may not exist).
std::string gps_dir();
/// The 241 218 GPS phase points from ../shared, or nullopt when ../shared is absent.
std::optional<std::vector<double>> gps_phase();

/// NIST SP1065 1000-point frequency set: n_{k+1} = 16807 n_k mod 2147483647, n_0 = 1234567890.
std::vector<double> nbs14_1000();

}  // namespace gyroflip::test
