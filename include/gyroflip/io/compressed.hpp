/// \file
/// \brief Compressed input read as it is decompressed (docs/FORMATS.md, "Compressed files"):
/// `.gz` (zlib), `.xz` (liblzma), `.zst` (libzstd), never unpacked to disk.
///
/// A file's compression is told by its name's last extension and checked against its first bytes
/// (the formats' magic numbers, FACTS §10). Concatenated members, streams or frames (pigz,
/// `cat a.gz b.gz`) are read one after another, as gzip -d, xz -d and zstd -d read them. A stream
/// that stops before its end marker (a file cut short) or whose check fails is an error naming the
/// file and the compressed byte, never a shorter input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gyroflip/core/result.hpp"

namespace gyroflip::io {

enum class compression { none, gzip, xz, zstd };

/// The compression `path`'s name announces (`.gz`, `.xz`, `.zst`), else none.
[[nodiscard]] compression compression_of(std::string_view path) noexcept;

/// `path` without its compression extension (`a.csv.gz` -> `a.csv`): the name that tells the
/// format of what is inside.
[[nodiscard]] std::string_view without_compression(std::string_view path) noexcept;

/// The bytes of a compressed file, decompressed a block at a time.
class decompressor {
 public:
  /// Opens `path` (compressed as its name says; its magic must agree). Errors: missing,
  /// a directory, not a regular file, magic of another format.
  [[nodiscard]] static result<std::unique_ptr<decompressor>> open(const std::string& path);
  decompressor(const decompressor&) = delete;
  decompressor& operator=(const decompressor&) = delete;
  decompressor(decompressor&&) = delete;
  decompressor& operator=(decompressor&&) = delete;
  virtual ~decompressor();

  /// Up to `n` decompressed bytes into `out`; 0 at the end of the last member. Errors (corrupt
  /// data, a stream cut short) as `FILE: what at compressed byte K`.
  [[nodiscard]] virtual result<std::size_t> read(char* out, std::size_t n) = 0;

 protected:
  decompressor(const std::string& path, int fd);
  /// Compressed input at in_[in_pos_, in_len_): true while some is left, else the next block
  /// is read (the used one counted in in_done_); false at the file's end. Errors: read(2).
  [[nodiscard]] result<bool> more_input();
  [[nodiscard]] error corrupt(std::string_view what) const;

  std::string path_;
  int fd_ = -1;
  std::uint64_t in_done_ = 0;  ///< compressed bytes used before in_ (for errors' positions)
  std::vector<unsigned char> in_;
  std::size_t in_len_ = 0, in_pos_ = 0;
  bool in_end_ = false;
};

/// A whole file's bytes in memory, decompressed when its name says it is compressed (for the
/// binary readers: .npy, raw, ROS bags). `max_bytes` bounds what decompression may produce (a
/// "zip bomb" fails with an error, not an exhausted machine). Errors as decompressor.
[[nodiscard]] result<std::vector<char>> read_decompressed(const std::string& path,
                                                          std::size_t max_bytes);

}  // namespace gyroflip::io
