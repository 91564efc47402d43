/// \file
/// \brief Columns of numbers as an HDF5 file (`gyroflip export -o RUN.h5`): each column a 1-D
/// float64 dataset at the root with a `unit` attribute, and `key: value` metadata as string
/// attributes of the root group. Built in memory (HDF5's core driver) and returned as the file's
/// bytes, so the caller writes it like any other output (io/atomic_file.hpp).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/io/csv.hpp"

namespace gyroflip::io {

struct hdf5_column {
  std::string name;  ///< dataset name (no '/')
  std::string unit;  ///< `unit` attribute ("s", "deg", "deg/s", "degC", "g", "1")
  std::vector<double> values;
};

/// The bytes of an HDF5 file holding `columns` and `attributes`. Errors: a non-finite value
/// (nothing written is ever NaN or infinite), columns of different lengths, an HDF5 failure.
[[nodiscard]] result<std::vector<std::uint8_t>> hdf5_table_image(
    std::span<const hdf5_column> columns, std::span<const csv_metadata> attributes);

}  // namespace gyroflip::io
