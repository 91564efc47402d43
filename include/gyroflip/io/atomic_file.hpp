/// \file
/// \brief Write-to-temporary-then-rename output files, so a failed run leaves no partial file.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

#include "gyroflip/core/result.hpp"

namespace gyroflip::io {

/// An output file that appears under its final name only when `commit()` succeeds.
/// Data go to `<path>.tmp.<pid>` in the same directory; the destructor removes the temporary
/// if `commit()` was not called (error paths, exceptions). `-` means standard output.
class atomic_file {
 public:
  /// Opens the temporary file. Errors: directory missing or not writable.
  [[nodiscard]] static result<atomic_file> create(std::string path);

  atomic_file(atomic_file&& other) noexcept;
  atomic_file& operator=(atomic_file&&) = delete;
  atomic_file(const atomic_file&) = delete;
  atomic_file& operator=(const atomic_file&) = delete;
  ~atomic_file();

  /// The stream to write to (stdout for `-`).
  [[nodiscard]] std::FILE* stream() const noexcept { return file_; }
  void write(std::string_view text) const;

  /// Flushes, closes and renames into place. Errors: write or rename failed (disk full, ...).
  [[nodiscard]] status commit();

 private:
  atomic_file(std::string path, std::string temp, std::FILE* f) noexcept;
  std::string path_;
  std::string temp_;  // empty for stdout
  std::FILE* file_ = nullptr;
};

/// Writes `text` to `path` atomically (convenience for small outputs such as JSON).
[[nodiscard]] status write_file_atomically(const std::string& path, std::string_view text);

}  // namespace gyroflip::io
