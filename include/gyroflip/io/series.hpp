/// \file
/// \brief A 1-D series of samples for analysis (`gyroflip adev`, `gyroflip noise`), read from a
/// CSV column, a NumPy `.npy` file, raw little-endian float64 or an HDF5 dataset (docs/FORMATS.md,
/// "Series").
///
/// `.npy` and raw files are memory-mapped and not copied, so a 1e9-sample file costs address
/// space, not heap: read through `samples()`, consumed pages are handed back to the kernel as the
/// analysis moves on, so resident memory stays a few hundred MB whatever the length. CSV columns
/// and HDF5 datasets are read into memory (8 bytes a sample).
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gyroflip/analysis/sample_source.hpp"
#include "gyroflip/core/result.hpp"
#include "gyroflip/io/csv.hpp"

namespace gyroflip::io {

/// What a CSV's time stamps may do between samples (docs/FORMATS.md, "Time stamps").
enum class gap_policy {
  error,  ///< a gap is an error that names where it is
  split,  ///< the longest gap-free run is analysed (series::notes says which)
  /// Each gap is bridged by samples interpolated linearly between its neighbours, as long as
  /// they are at most 1 % of the samples (series::notes says how many); more is an error.
  fill,
};

/// The share of a record's samples that gap_policy::fill may interpolate: at least 99 % of the
/// samples analysed are measured (issue 34).
inline constexpr double max_filled_fraction = 0.01;

struct series_options {
  std::string column = "rate_dps";  ///< CSV column to read (a name, or a number from 1)
  /// For .npy, raw and HDF5 input the sample rate (required unless the file has one). With a
  /// CSV time column it must agree with the stamps' rate within 1 %, and is then used as the
  /// exact rate; without one it gives the rate.
  std::optional<double> sample_rate_hz;
  std::string dataset;  ///< HDF5 dataset path (or give FILE.h5:/path)
  /// ROS bag topic of sensor_msgs/Imu messages (or give FILE.bag:/topic); empty: the bag's only
  /// IMU topic. Columns: io::imu_columns (or the message fields, io::imu_fields).
  std::string topic;
  csv_dialect dialect;  ///< how the CSV is written
  /// CSV time column; empty: `time_s` when the file has one.
  std::string time_column;
  double time_unit_s = 1.0;  ///< seconds per unit of the time column (1e-9 for ns stamps)
  gap_policy gaps = gap_policy::error;
};

/// Samples plus their spacing, from a mapped file or held in memory.
class series {
 public:
  /// The samples for analysis::phase_source: views of the mapped file whose pages are dropped
  /// from the process as they are released (every 2^18 samples consumed), or of the samples in
  /// memory.
  [[nodiscard]] const analysis::sample_source& samples() const noexcept { return *samples_; }
  /// All samples at once (for a mapped file every page read stays resident: short files only).
  [[nodiscard]] std::span<const double> values() const noexcept {
    return samples_->view(0, samples_->size());
  }
  [[nodiscard]] double tau0_s() const noexcept { return tau0_s_; }
  [[nodiscard]] const std::string& source() const noexcept { return source_; }
  /// A CSV recording's `angle_deg` per sample (NaN while the table turns); empty when the file
  /// has no such column (or is not CSV).
  [[nodiscard]] const std::vector<double>& angle_deg() const noexcept { return angle_deg_; }
  /// The `# key: value` lines before a CSV's first row (empty for other formats).
  [[nodiscard]] const std::vector<csv_metadata>& metadata() const noexcept { return metadata_; }
  /// What the reader noticed and the user should know (time-stamp jitter, the run analysed
  /// after a gap), one sentence each.
  [[nodiscard]] const std::vector<std::string>& notes() const noexcept { return notes_; }
  /// The ROS bag topic the samples came from (empty for other formats).
  [[nodiscard]] const std::string& topic() const noexcept { return topic_; }

  series(series&&) noexcept = default;
  series& operator=(series&&) noexcept = default;
  series(const series&) = delete;
  series& operator=(const series&) = delete;
  ~series() = default;

 private:
  friend result<series> read_series(const std::string& path, const series_options& opt);
  friend result<std::vector<series>> read_series_columns(const std::string& path,
                                                         const series_options& opt,
                                                         const std::vector<std::string>& columns);
  friend result<series> series_of_samples(std::string source, std::vector<double> values,
                                          std::span<const double> time_s,
                                          std::vector<double> angle_deg,
                                          std::vector<csv_metadata> metadata);
  series() = default;
  void hold(std::vector<double> values);
  std::vector<double> owned_;
  std::unique_ptr<analysis::sample_source> samples_;
  double tau0_s_ = 0.0;
  std::string source_;
  std::vector<csv_metadata> metadata_;
  std::vector<double> angle_deg_;
  std::vector<std::string> notes_;
  std::string topic_;
};

/// The file a series input names: FILE.h5 for `FILE.h5:/dataset` (also .hdf5, .hdf), else the
/// name itself. For checks on the file (an output must not replace an input).
[[nodiscard]] std::string series_file(const std::string& spec);

/// Reads `path` by its extension: `.npy` (1-D, '<f8', C order), `.f64`/`.bin`/`.raw` (raw
/// little-endian float64), `.h5`/`.hdf5` (a 1-D dataset named `FILE.h5:/path` or by
/// `dataset`, any numeric type, rate from a `sample_rate_hz` attribute or the option),
/// anything else CSV (in `dialect`). For CSV the sample interval comes from the time column's
/// stamps (rebased to the first before any arithmetic, so that epoch nanoseconds keep their
/// precision): the median step is the period; steps within +-50 % of it are jitter (accepted
/// and noted); a longer step is a gap (an error naming where, or with gap_policy::split the
/// longest gap-free run); a shorter one, or stamps that drift off a uniform grid by half a
/// period, is an error. Errors name the file (and line/column for CSV); `FILE.h5:/a` with the
/// `dataset` option naming another dataset is an error (which one was meant cannot be guessed).
[[nodiscard]] result<series> read_series(const std::string& path, const series_options& opt);

/// Several CSV columns read in one pass over the file (an N x M logger file): one series each,
/// sharing the time stamps, their checks and notes. Columns by name or number from 1.
[[nodiscard]] result<std::vector<series>> read_series_columns(
    const std::string& path, const series_options& opt, const std::vector<std::string>& columns);

/// The names of a CSV's numeric columns: those whose first data row holds a number, without the
/// time column and a flip recording's angle_deg.
[[nodiscard]] result<std::vector<std::string>> numeric_columns(const std::string& path,
                                                               const series_options& opt);

/// A series from samples already in memory (a rig recording read back): `time_s` per sample must
/// lie on a uniform grid (each within half a step), which gives the interval; `angle_deg` per
/// sample or empty. `source` names it in messages.
[[nodiscard]] result<series> series_of_samples(std::string source, std::vector<double> values,
                                               std::span<const double> time_s,
                                               std::vector<double> angle_deg,
                                               std::vector<csv_metadata> metadata);

}  // namespace gyroflip::io
