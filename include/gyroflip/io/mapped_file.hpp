/// \file
/// \brief A read-only memory-mapped file (regular files only).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

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

}  // namespace gyroflip::io
