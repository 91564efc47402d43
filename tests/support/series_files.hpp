/// \file
/// \brief Writes sample series as the binary files `gyroflip adev` reads: NumPy .npy (format
/// 1.0, 1-D, C order) and raw little-endian float64 (docs/FORMATS.md, "Series").
#pragma once

#include <string>
#include <vector>

namespace gyroflip::test {

/// `values` as a .npy file whose header says dtype `descr` (the data are float64 regardless, so
/// another descr makes a file the reader must refuse).
void write_npy(const std::string& path, const std::vector<double>& values,
               const std::string& descr = "<f8");

/// `values` as raw little-endian float64.
void write_f64(const std::string& path, const std::vector<double>& values);

}  // namespace gyroflip::test
