/// \file
/// \brief Private: reads a 1-D HDF5 dataset as doubles (used by series.cpp only).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::io::detail {

struct hdf5_data {
  std::vector<double> values;
  std::optional<double> sample_rate_hz;  ///< from a `sample_rate_hz` attribute of the dataset
};

/// Reads dataset `dataset` (e.g. "/gyro/rate_x") of `file`: a 1-D dataset, or `column` (0-based)
/// of a 2-D one (samples x columns). Errors name the file.
[[nodiscard]] result<hdf5_data> read_hdf5_dataset(const std::string& file,
                                                  const std::string& dataset,
                                                  std::optional<std::size_t> column = {});

}  // namespace gyroflip::io::detail
