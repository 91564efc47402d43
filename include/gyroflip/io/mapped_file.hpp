/// \file
/// \brief A read-only memory-mapped file (regular files only).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "gyroflip/analysis/sample_source.hpp"
#include "gyroflip/core/result.hpp"

namespace gyroflip::io {

/// Maps a whole regular file read-only. Errors (as `FILE: what`): missing, a directory,
/// not a regular file, unreadable. An empty file maps to an empty view.
class mapped_file {
 public:
  [[nodiscard]] static result<mapped_file> open(const std::string& path);
  mapped_file(mapped_file&& other) noexcept;
  mapped_file& operator=(mapped_file&& other) noexcept;
  mapped_file(const mapped_file&) = delete;
  mapped_file& operator=(const mapped_file&) = delete;
  ~mapped_file();

  [[nodiscard]] std::string_view data() const noexcept { return {ptr_, size_}; }
  [[nodiscard]] const std::string& path() const noexcept { return path_; }

  /// Drops the resident pages of bytes [begin, end) (rounded outward to multiples of `granule`
  /// bytes of address, at least whole pages): they stop counting in the process's memory and are
  /// read again from the page cache if touched, so dropping a page another reader still uses
  /// costs a page fault, not data.
  void release(std::size_t begin, std::size_t end, std::size_t granule = 0) const noexcept;

 private:
  mapped_file(std::string path, const char* p, std::size_t n) noexcept;
  std::string path_;
  const char* ptr_ = nullptr;
  std::size_t size_ = 0;
};

/// Drops the resident pages of bytes [begin, end) of the file mapping whose bytes start at `base`
/// and run `size` bytes (rounded outward to multiples of `granule` bytes of address, at least
/// whole pages, but never past the pages that hold bytes [0, size)). For a shared mapping of a
/// file (read-only or not) the pages are read again from the page cache when touched; on private
/// or anonymous memory it would DISCARD data, so callers pass only shared file mappings.
void drop_pages(const char* base, std::size_t size, std::size_t begin, std::size_t end,
                std::size_t granule) noexcept;

/// Float64 samples in memory that a shared file mapping holds (this one's or another library's,
/// e.g. a NumPy memmap), not owned: released samples leave the process's resident memory
/// (docs/ANALYSIS.md, "memory"). A series below 2^25 samples stays resident: releasing it would
/// only make every further pass (an Allan sweep per group of factors) fault it in again.
class mapping_samples : public analysis::sample_source {
 public:
  mapping_samples(const double* data, std::size_t count) noexcept : data_(data), count_(count) {}
  [[nodiscard]] std::size_t size() const noexcept override { return count_; }
  [[nodiscard]] std::span<const double> view(std::size_t begin,
                                             std::size_t count) const noexcept override {
    return {data_ + begin, count};
  }
  // Whole 64 KB windows of address: a page fault maps the aligned 64 KB around it (the kernel's
  // default fault-around), which a release of only the pages read would leave resident.
  void release(std::size_t begin, std::size_t end) const noexcept override;
  static constexpr std::size_t keep_resident_samples = std::size_t{1} << 25;
  // 2 MB: one madvise per 2 MB consumed per reader (cheap), ~100 MB resident at most.
  [[nodiscard]] std::size_t release_step() const noexcept override { return std::size_t{1} << 18; }

 private:
  const double* data_;
  std::size_t count_;
};

}  // namespace gyroflip::io
