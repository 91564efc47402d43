/// \file
/// \brief .gz, .xz and .zst input through zlib, liblzma and libzstd (see compressed.hpp).
#include "gyroflip/io/compressed.hpp"

#include <fcntl.h>
#include <lzma.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include <zstd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <limits>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::io {

namespace {

constexpr std::size_t in_block = std::size_t{1} << 16;

struct format_facts {
  std::string_view extension;
  std::string_view name;
  std::string_view magic;
};

// The magic numbers: RFC 1952 section 2.3.1 (ID1 ID2 = 1f 8b), the .xz file format 1.1.0
// section 2.1.1.1 (fd 37 7a 58 5a 00), RFC 8878 section 3.1.1 (28 b5 2f fd, little-endian
// 0xFD2FB528).
constexpr std::array<format_facts, 3> formats{{
    {".gz", "gzip", std::string_view("\x1f\x8b", 2)},
    {".xz", "xz", std::string_view("\xfd\x37\x7a\x58\x5a\x00", 6)},
    {".zst", "zstd", std::string_view("\x28\xb5\x2f\xfd", 4)},
}};

const format_facts& facts_of(compression c) {
  return formats[static_cast<std::size_t>(c) - 1];
}

}  // namespace

compression compression_of(std::string_view path) noexcept {
  for (std::size_t i = 0; i < formats.size(); ++i)
    if (path.ends_with(formats[i].extension)) return static_cast<compression>(i + 1);
  return compression::none;
}

std::string_view without_compression(std::string_view path) noexcept {
  const auto c = compression_of(path);
  if (c == compression::none) return path;
  return path.substr(0, path.size() - facts_of(c).extension.size());
}

decompressor::decompressor(const std::string& path, int fd) : path_(path), fd_(fd), in_(in_block) {}

decompressor::~decompressor() {
  if (fd_ >= 0) ::close(fd_);
}

result<bool> decompressor::more_input() {
  if (in_pos_ < in_len_) return true;
  if (in_end_) return false;
  in_done_ += in_len_;
  in_pos_ = 0;
  in_len_ = 0;
  while (true) {
    const ssize_t n = ::read(fd_, in_.data(), in_.size());
    if (n > 0) {
      in_len_ = static_cast<std::size_t>(n);
      return true;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return io_error(path_, std::strerror(errno));
    in_end_ = true;
    return false;
  }
}

error decompressor::corrupt(std::string_view what) const {
  return input_error({path_}, fmt::format("{} at compressed byte {} (a damaged or truncated file)",
                                          what, in_done_ + in_pos_));
}

namespace {

// gzip (RFC 1952) through zlib's inflate with automatic header detection; members one after
// another.
class gzip_reader final : public decompressor {
 public:
  gzip_reader(const std::string& path, int fd) : decompressor(path, fd) {}
  ~gzip_reader() override {
    if (started_) inflateEnd(&z_);
  }
  gzip_reader(const gzip_reader&) = delete;
  gzip_reader& operator=(const gzip_reader&) = delete;
  gzip_reader(gzip_reader&&) = delete;
  gzip_reader& operator=(gzip_reader&&) = delete;

  result<std::size_t> read(char* out, std::size_t n) override {
    std::size_t got = 0;
    while (got == 0 && n > 0) {
      auto more = more_input();
      if (!more) return more.err();
      if (!*more) {
        if (!started_ || member_open_) return corrupt("the gzip stream ends early");
        return std::size_t{0};
      }
      if (!started_) {
        z_ = {};
        // 15 + 16: a gzip header and trailer (CRC-32 and length checked by zlib).
        if (inflateInit2(&z_, 15 + 16) != Z_OK) return runtime_error("zlib: out of memory");
        started_ = true;
        member_open_ = true;
      } else if (!member_open_) {
        if (inflateReset(&z_) != Z_OK) return corrupt("zlib cannot start the next member");
        member_open_ = true;
      }
      z_.next_in = in_.data() + in_pos_;
      z_.avail_in = static_cast<uInt>(in_len_ - in_pos_);
      z_.next_out = reinterpret_cast<Bytef*>(out);  // NOLINT: zlib's byte type
      const auto room = static_cast<uInt>(std::min<std::size_t>(n, std::size_t{1} << 30));
      z_.avail_out = room;
      const int rc = inflate(&z_, Z_NO_FLUSH);
      in_pos_ = in_len_ - z_.avail_in;
      got = room - z_.avail_out;
      if (rc == Z_STREAM_END) {
        member_open_ = false;
      } else if (rc != Z_OK && rc != Z_BUF_ERROR) {
        return corrupt(fmt::format("gzip: {}", z_.msg != nullptr ? z_.msg : "corrupt data"));
      }
    }
    return got;
  }

 private:
  z_stream z_{};
  bool started_ = false;
  bool member_open_ = false;
};

// xz (the .xz file format 1.1.0) through liblzma; concatenated streams and their padding read.
class xz_reader final : public decompressor {
 public:
  xz_reader(const std::string& path, int fd) : decompressor(path, fd) {}
  ~xz_reader() override { lzma_end(&s_); }
  xz_reader(const xz_reader&) = delete;
  xz_reader& operator=(const xz_reader&) = delete;
  xz_reader(xz_reader&&) = delete;
  xz_reader& operator=(xz_reader&&) = delete;

  result<std::size_t> read(char* out, std::size_t n) override {
    if (!started_) {
      if (lzma_stream_decoder(&s_, std::numeric_limits<std::uint64_t>::max(), LZMA_CONCATENATED) !=
          LZMA_OK)
        return runtime_error("liblzma: cannot start a decoder");
      started_ = true;
    }
    if (done_) return std::size_t{0};
    std::size_t got = 0;
    while (got == 0 && n > 0) {
      auto more = more_input();
      if (!more) return more.err();
      const lzma_action action = *more ? LZMA_RUN : LZMA_FINISH;
      s_.next_in = in_.data() + in_pos_;
      s_.avail_in = in_len_ - in_pos_;
      s_.next_out = reinterpret_cast<std::uint8_t*>(out);  // NOLINT: liblzma's byte type
      s_.avail_out = n;
      const lzma_ret rc = lzma_code(&s_, action);
      in_pos_ = in_len_ - s_.avail_in;
      got = n - s_.avail_out;
      if (rc == LZMA_STREAM_END) {
        done_ = true;
        return got;
      }
      if (rc == LZMA_BUF_ERROR && action == LZMA_FINISH) return corrupt("the xz stream ends early");
      if (rc != LZMA_OK)
        return corrupt(rc == LZMA_DATA_ERROR     ? "xz: corrupt data"
                       : rc == LZMA_FORMAT_ERROR ? "xz: not an xz stream"
                       : rc == LZMA_MEM_ERROR    ? "xz: out of memory"
                                                 : "xz: the integrity check fails");
      if (action == LZMA_FINISH && got == 0) return corrupt("the xz stream ends early");
    }
    return got;
  }

 private:
  lzma_stream s_ = LZMA_STREAM_INIT;
  bool started_ = false;
  bool done_ = false;
};

// zstd (RFC 8878) through libzstd's streaming decoder; frames one after another.
class zstd_reader final : public decompressor {
 public:
  zstd_reader(const std::string& path, int fd) : decompressor(path, fd), d_(ZSTD_createDStream()) {}
  ~zstd_reader() override { ZSTD_freeDStream(d_); }
  zstd_reader(const zstd_reader&) = delete;
  zstd_reader& operator=(const zstd_reader&) = delete;
  zstd_reader(zstd_reader&&) = delete;
  zstd_reader& operator=(zstd_reader&&) = delete;

  result<std::size_t> read(char* out, std::size_t n) override {
    if (d_ == nullptr) return runtime_error("libzstd: out of memory");
    std::size_t got = 0;
    while (got == 0 && n > 0) {
      auto more = more_input();
      if (!more) return more.err();
      if (!*more) {
        if (!seen_ || frame_open_) return corrupt("the zstd stream ends early");
        return std::size_t{0};
      }
      seen_ = true;
      ZSTD_inBuffer in{in_.data() + in_pos_, in_len_ - in_pos_, 0};
      ZSTD_outBuffer o{out, n, 0};
      const std::size_t rc = ZSTD_decompressStream(d_, &o, &in);
      in_pos_ += in.pos;
      got = o.pos;
      if (ZSTD_isError(rc) != 0U) return corrupt(fmt::format("zstd: {}", ZSTD_getErrorName(rc)));
      // 0: a frame is complete and flushed; more input starts the next.
      frame_open_ = rc != 0;
    }
    return got;
  }

 private:
  ZSTD_DStream* d_;
  bool seen_ = false;
  bool frame_open_ = false;
};

}  // namespace

result<std::unique_ptr<decompressor>> decompressor::open(const std::string& path) {
  const compression c = compression_of(path);
  if (c == compression::none) return usage_error("not a compressed file name: " + path);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return io_error(path, std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    const bool dir = S_ISDIR(st.st_mode);
    ::close(fd);
    return io_error(path, dir ? "is a directory, not a file" : "not a regular file");
  }
  const auto& f = facts_of(c);
  std::array<char, 8> head{};
  const ssize_t got = ::pread(fd, head.data(), head.size(), 0);
  if (got < static_cast<ssize_t>(f.magic.size()) ||
      std::string_view(head.data(), f.magic.size()) != f.magic) {
    ::close(fd);
    return input_error({path}, got == 0 ? fmt::format("empty file (expected {} data)", f.name)
                                        : fmt::format("not {} data (its name ends in {}, its "
                                                      "first bytes are not {}'s magic number)",
                                                      f.name, f.extension, f.name));
  }
  ::posix_fadvise(fd, 0, 0, POSIX_FADV_SEQUENTIAL);
  std::unique_ptr<decompressor> d;
  if (c == compression::gzip) d = std::make_unique<gzip_reader>(path, fd);
  if (c == compression::xz) d = std::make_unique<xz_reader>(path, fd);
  if (c == compression::zstd) d = std::make_unique<zstd_reader>(path, fd);
  return d;
}

result<std::vector<char>> read_decompressed(const std::string& path, std::size_t max_bytes) {
  auto d = decompressor::open(path);
  if (!d) return d.err();
  std::vector<char> out;
  constexpr std::size_t block = std::size_t{1} << 18;
  while (true) {
    const std::size_t at = out.size();
    out.resize(at + block);
    auto n = (*d)->read(out.data() + at, block);
    if (!n) return n.err();
    out.resize(at + *n);
    if (*n == 0) break;
    if (out.size() > max_bytes)
      return input_error({path}, fmt::format("decompresses to more than {} bytes (the limit for "
                                             "a file read whole)",
                                             max_bytes));
  }
  return out;
}

}  // namespace gyroflip::io
