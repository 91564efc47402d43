/// \file
/// \brief Reading and appending `.gfr` recordings (gfr.hpp, docs/FORMATS.md).
#include "gyroflip/rigdata/gfr.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <utility>

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::rigdata::gfr {

namespace {

void put_u16(std::vector<std::uint8_t>& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v));
  b.push_back(static_cast<std::uint8_t>(v >> 8));
}
void put_u32(std::vector<std::uint8_t>& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_u64(std::vector<std::uint8_t>& b, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

// The little-endian unsigned integer of `bytes` (1..8) bytes at `p`.
std::uint64_t load_le(const std::uint8_t* p, int bytes) noexcept {
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

std::vector<std::uint8_t> file_header() {
  std::vector<std::uint8_t> h(magic.begin(), magic.end());
  put_u16(h, format_version);
  put_u16(h, 0);
  put_u32(h, crc32(h));
  return h;
}

bool known_kind(std::uint8_t k) {
  return k >= static_cast<std::uint8_t>(kind::meta) && k <= static_cast<std::uint8_t>(kind::stop);
}

error at_record(const std::string& name, std::size_t n, const std::string& what) {
  return input_error({name}, fmt::format("record {}: {}", n, what));
}

// A failed write or sync of the recording: a full disk (or a failing one) is a condition of the
// run (exit 1), not of what the user asked for.
error write_error(const std::string& path, const std::string& what, int err) {
  const std::string m = what + std::strerror(err);
  if (err == ENOSPC || err == EDQUOT || err == EIO || err == EFBIG)
    return runtime_error(path + ": " + m);
  return io_error(path, m);
}

status check_file_header(std::span<const std::uint8_t> b, const std::string& name) {
  if (b.size() < magic.size() || std::memcmp(b.data(), magic.data(), magic.size()) != 0)
    return at_record(name, 0,
                     "not a gyroflip rig recording (the file does not start with the "
                     ".gfr magic bytes)");
  if (b.size() < file_header_bytes)
    return at_record(
        name, 0,
        fmt::format("the file header is cut short ({} of {} bytes)", b.size(), file_header_bytes));
  if (load_le(b.data() + 12, 4) != crc32(b.first(12)))
    return at_record(name, 0, "file header checksum mismatch (the file is damaged)");
  const auto version = static_cast<std::uint16_t>(load_le(b.data() + 8, 2));
  if (version > format_version)
    return at_record(name, 0,
                     fmt::format("format version {} is newer than this gyroflip reads "
                                 "({}): update gyroflip",
                                 version, format_version));
  if (version == 0) return at_record(name, 0, "format version 0 does not exist");
  return ok();
}

}  // namespace

std::uint32_t crc32(std::span<const std::uint8_t> bytes) noexcept {
  uLong c = ::crc32(0L, Z_NULL, 0);
  // zlib takes uInt lengths: feed in pieces below 4 GiB.
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t n = std::min<std::size_t>(bytes.size() - done, std::size_t{1} << 30);
    c = ::crc32(c, bytes.data() + done, static_cast<uInt>(n));
    done += n;
  }
  return static_cast<std::uint32_t>(c);
}

namespace {

// The record at `at` when it is intact: its length (with length field, check and CRC), else 0.
std::size_t intact_record(std::span<const std::uint8_t> b, std::size_t at) {
  const std::size_t left = b.size() - at;
  if (left < record_overhead) return 0;
  const std::uint64_t len = load_le(b.data() + at, 4);
  if ((len ^ 0xFFFFFFFFU) != load_le(b.data() + at + 4, 4)) return 0;
  if (len < 9 || len - 9 > max_body) return 0;
  const std::size_t whole = static_cast<std::size_t>(len) + 12;
  if (whole > left) return 0;
  const auto rec = b.subspan(at, whole);
  if (load_le(rec.data() + whole - 4, 4) != crc32(rec.first(whole - 4))) return 0;
  return known_kind(rec[8]) ? whole : 0;
}

bool all_zero(std::span<const std::uint8_t> b) {
  return std::all_of(b.begin(), b.end(), [](std::uint8_t v) { return v == 0; });
}

}  // namespace

result<file> parse(std::span<const std::uint8_t> b, const std::string& name, bool strict) {
  if (auto s = check_file_header(b, name); !s) return s.err();
  file out;
  std::size_t at = file_header_bytes;
  for (std::size_t n = 1; at < b.size(); ++n) {
    if (const std::size_t whole = intact_record(b, at); whole != 0) {
      const auto rec = b.subspan(at, whole);
      if (n == 1 && static_cast<kind>(rec[8]) != kind::meta)
        return at_record(name, n, "the first record is not META");
      out.records.push_back({static_cast<kind>(rec[8]), load_le(rec.data() + 9, 8),
                             std::vector<std::uint8_t>(rec.begin() + 17, rec.end() - 4)});
      at += whole;
      continue;
    }
    const std::size_t left = b.size() - at;
    // Another recording's header here: two files were joined (`cat a.gfr b.gfr`).
    if (left >= magic.size() && std::memcmp(b.data() + at, magic.data(), magic.size()) == 0)
      return at_record(name, n,
                       fmt::format("offset {}: the header of another recording: two .gfr files "
                                   "were joined into one; split them there",
                                   at));
    // Zeros to the end: what a power loss leaves after the last write (the file's size was
    // extended, its data never written).
    if (all_zero(b.subspan(at))) {
      out.warnings.push_back(fmt::format(
          "{}: record {}: the last {} bytes are zeros (a power loss during writing); ignored", name,
          n, left));
      break;
    }
    // META holds the conversion to physical units: without it nothing reads.
    if (n == 1)
      return at_record(name, 1, "the META record is damaged (its checksum does not match)");
    std::size_t next = at + 1;
    while (next < b.size() && intact_record(b, next) == 0) ++next;
    if (next >= b.size()) {
      // Nothing intact after it: a record cut off while it was written (a hard stop).
      out.warnings.push_back(fmt::format(
          "{}: record {}: the last {} bytes are a record cut off while it was written (the "
          "recorder was stopped hard); ignored",
          name, n, left));
      break;
    }
    if (strict)
      return at_record(
          name, n,
          fmt::format("damaged: {} bytes from offset {} are no intact record", next - at, at));
    out.warnings.push_back(fmt::format(
        "{}: record {}: {} damaged bytes at offsets {}..{} skipped; reading goes on at the next "
        "intact record (every record is checked by its CRC-32)",
        name, n, next - at, at, next - 1));
    at = next;
  }
  if (out.records.empty())
    return at_record(name, 1, "no META record: the recorder stopped before it wrote anything");
  return out;
}

result<file> read(const std::string& path, bool strict) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    return io_error(path, "is a directory, not a .gfr recording");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return io_error(path, std::string("cannot open: ") + std::strerror(errno));
  std::vector<std::uint8_t> bytes;
  std::uint8_t buf[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.insert(bytes.end(), buf, buf + got);
  const bool failed = std::ferror(f) != 0;
  const int err = errno;
  std::fclose(f);
  if (failed) return io_error(path, std::string("read failed: ") + std::strerror(err));
  return parse(bytes, path, strict);
}

result<writer> writer::create(const std::string& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    if (errno == EEXIST)
      return io_error(path, "exists; a recording is never overwritten (choose another name)");
    return io_error(path, std::string("cannot create: ") + std::strerror(errno));
  }
  writer w(fd, path);
  // A file this call made and could not start is removed: no empty recording is left behind
  // (a full disk).
  const auto fail = [&](const std::string& what) {
    const int err = errno;
    (void)::close(std::exchange(w.fd_, -1));
    (void)::unlink(path.c_str());
    return write_error(path, what, err);
  };
  const auto h = file_header();
  if (::write(fd, h.data(), h.size()) != static_cast<ssize_t>(h.size())) return fail("write: ");
  w.bytes_ = h.size();
  if (::fdatasync(fd) != 0) return fail("fsync: ");
  // The new name must survive a power loss too: sync the folder that holds it.
  const std::string dir = std::filesystem::path(path).parent_path().empty()
                              ? std::string(".")
                              : std::filesystem::path(path).parent_path().string();
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0 || ::fsync(dfd) != 0) {
    if (dfd >= 0) ::close(dfd);
    return fail("fsync of its folder: ");
  }
  ::close(dfd);
  return w;
}

writer::writer(writer&& o) noexcept
    : fd_(std::exchange(o.fd_, -1)),
      path_(std::move(o.path_)),
      bytes_(o.bytes_),
      buf_(std::move(o.buf_)) {}

writer& writer::operator=(writer&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
    path_ = std::move(o.path_);
    bytes_ = o.bytes_;
    buf_ = std::move(o.buf_);
  }
  return *this;
}

writer::~writer() {
  if (fd_ >= 0) ::close(fd_);
}

status writer::append(kind k, std::uint64_t host_time_us, std::span<const std::uint8_t> body) {
  if (body.size() > max_body) return runtime_error("a .gfr record body over 1 MiB");
  buf_.clear();
  const auto len = static_cast<std::uint32_t>(body.size() + 9);
  put_u32(buf_, len);
  put_u32(buf_, len ^ 0xFFFFFFFFU);
  buf_.push_back(static_cast<std::uint8_t>(k));
  put_u64(buf_, host_time_us);
  buf_.insert(buf_.end(), body.begin(), body.end());
  put_u32(buf_, crc32(buf_));
  // One write per record: a kill between records leaves whole ones only, and one inside the
  // write leaves a torn tail the reader skips.
  std::size_t done = 0;
  while (done < buf_.size()) {
    const ssize_t n = ::write(fd_, buf_.data() + done, buf_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return write_error(path_, "write: ", errno);
    done += static_cast<std::size_t>(n);
  }
  bytes_ += buf_.size();
  return ok();
}

status writer::sync() {
  if (::fdatasync(fd_) != 0) return write_error(path_, "fsync: ", errno);
  return ok();
}

status writer::close() {
  if (fd_ < 0) return ok();
  auto s = sync();
  const int rc = ::close(std::exchange(fd_, -1));
  if (!s) return s;
  if (rc != 0) return io_error(path_, std::string("close: ") + std::strerror(errno));
  return ok();
}

}  // namespace gyroflip::rigdata::gfr
