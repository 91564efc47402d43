/// \file
/// \brief Where the analysis reads its samples from: views of samples [begin, begin + count) on
/// demand, so that a long file need not be in memory at once. What the samples are (rate or
/// angle) is `input_kind`.
///
/// Provides the interface and `span_samples` (samples already in memory: CSV columns, HDF5
/// datasets, tests). The file-backed source (`.npy`, raw float64) is `io::series::samples()`.
/// Does not compute anything; `phase_source` turns samples into the phase series.
#pragma once

#include <cstddef>
#include <span>

namespace gyroflip::analysis {

/// What the samples are: angular rate (deg/s; SP1065 "frequency") or angle (deg; "phase").
enum class input_kind { rate, angle };

/// A read-only sequence of samples. Implementations must allow concurrent `view` and `release`
/// calls from several threads.
class sample_source {
 public:
  sample_source() = default;
  sample_source(const sample_source&) = delete;
  sample_source& operator=(const sample_source&) = delete;
  sample_source(sample_source&&) = delete;
  sample_source& operator=(sample_source&&) = delete;
  virtual ~sample_source() = default;

  /// Number of samples.
  [[nodiscard]] virtual std::size_t size() const noexcept = 0;
  /// Samples [begin, begin + count) (begin + count <= size()); the view stays valid while the
  /// source lives. Touching it may make the pages resident until `release`.
  [[nodiscard]] virtual std::span<const double> view(std::size_t begin,
                                                     std::size_t count) const noexcept = 0;
  /// Says that samples [begin, end) are not needed soon: a memory-mapped file drops their pages
  /// from the process (they are read again from the page cache if viewed again). No-op for
  /// samples held in memory.
  virtual void release(std::size_t begin, std::size_t end) const noexcept = 0;
  /// How many consumed samples a reader should collect before calling `release` (one call per
  /// step keeps the system calls rare while bounding what stays resident).
  [[nodiscard]] virtual std::size_t release_step() const noexcept = 0;
};

/// Samples held in memory by the caller (who keeps them alive and unchanged).
class span_samples final : public sample_source {
 public:
  explicit span_samples(std::span<const double> data) noexcept : data_(data) {}
  [[nodiscard]] std::size_t size() const noexcept override { return data_.size(); }
  [[nodiscard]] std::span<const double> view(std::size_t begin,
                                             std::size_t count) const noexcept override {
    return data_.subspan(begin, count);
  }
  void release(std::size_t /*begin*/, std::size_t /*end*/) const noexcept override {}
  [[nodiscard]] std::size_t release_step() const noexcept override { return data_.size() + 1; }

 private:
  std::span<const double> data_;
};

}  // namespace gyroflip::analysis
