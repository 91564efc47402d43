/// \file
/// \brief Writes sample series as the binary files `gyroflip adev` reads: NumPy .npy (format
/// 1.0, 1-D, C order), raw little-endian float64 and HDF5 datasets (docs/FORMATS.md, "Series").
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace gyroflip::test {

/// `values` as a .npy file whose header says dtype `descr` (the data are float64 regardless, so
/// another descr makes a file the reader must refuse).
void write_npy(const std::string& path, const std::vector<double>& values,
               const std::string& descr = "<f8");

/// `values` as raw little-endian float64.
void write_f64(const std::string& path, const std::vector<double>& values);

/// `values` as the 1-D dataset `dataset` ("/gyro/rate_x"; groups made as needed) of a new HDF5
/// file, stored as float32 or float64, with a `sample_rate_hz` attribute when one is given (as a
/// user's logger writes it).
void write_h5(const std::string& path, const std::string& dataset,
              const std::vector<double>& values, std::optional<double> sample_rate_hz,
              bool float32 = false);

}  // namespace gyroflip::test
