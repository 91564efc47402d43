/// \file
/// \brief A 1-D series of samples for analysis (`gyroflip adev`, `gyroflip noise`), read from a
/// CSV column, a NumPy `.npy` file, raw little-endian float64 or an HDF5 dataset (docs/FORMATS.md,
/// "Series").
///
/// `.npy` and raw files are memory-mapped and not copied, so a 1e9-sample file costs address
/// space, not heap; CSV columns are parsed into memory (8 bytes a sample).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/core/result.hpp"
#include "gyroflip/io/mapped_file.hpp"

namespace gyroflip::io {

struct series_options {
  std::string column = "rate_dps";       ///< CSV column to read
  std::optional<double> sample_rate_hz;  ///< overrides time_s; required for .npy and raw
  std::string dataset;                   ///< HDF5 dataset path (or give FILE.h5:/path)
};

/// Samples plus their spacing. `values()` views either the mapped file or `owned_`.
class series {
 public:
  [[nodiscard]] std::span<const double> values() const noexcept { return view_; }
  [[nodiscard]] double tau0_s() const noexcept { return tau0_s_; }
  [[nodiscard]] const std::string& source() const noexcept { return source_; }
  /// Lets go of samples [begin, end) of a memory-mapped input once they are consumed (no-op
  /// for inputs held in memory), so a long file is not resident twice.
  void release(std::size_t begin, std::size_t end) const noexcept;

  series(series&&) noexcept = default;
  series& operator=(series&&) noexcept = default;
  series(const series&) = delete;
  series& operator=(const series&) = delete;
  ~series() = default;

 private:
  friend result<series> read_series(const std::string& path, const series_options& opt);
  series() = default;
  std::optional<mapped_file> file_;
  std::vector<double> owned_;
  std::span<const double> view_;
  double tau0_s_ = 0.0;
  std::string source_;
};

/// Reads `path` by its extension: `.npy` (1-D, '<f8', C order), `.f64`/`.bin`/`.raw` (raw
/// little-endian float64), `.h5`/`.hdf5` (a 1-D dataset named `FILE.h5:/path` or by
/// `dataset`, any numeric type, rate from a `sample_rate_hz` attribute or the option),
/// anything else CSV. For CSV the sample interval comes from the
/// `time_s` column (uniform within 1e-6 relative, else an error naming the line) unless
/// `sample_rate_hz` is given. Errors name the file (and line/column for CSV).
[[nodiscard]] result<series> read_series(const std::string& path, const series_options& opt);

}  // namespace gyroflip::io
