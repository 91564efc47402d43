/// \file
/// \brief mmap-based read-only file view (see mapped_file.hpp).
#include "gyroflip/io/mapped_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <utility>

#include "gyroflip/core/error.hpp"

namespace gyroflip::io {

// cppcheck-suppress passedByValue ; sink parameter, moved from
mapped_file::mapped_file(std::string path, const char* p, std::size_t n) noexcept
    : path_(std::move(path)), ptr_(p), size_(n) {}

mapped_file::mapped_file(mapped_file&& other) noexcept
    : path_(std::move(other.path_)),
      ptr_(std::exchange(other.ptr_, nullptr)),
      size_(std::exchange(other.size_, 0)) {}

mapped_file& mapped_file::operator=(mapped_file&& other) noexcept {
  if (this != &other) {
    if (ptr_ != nullptr && size_ != 0) ::munmap(const_cast<char*>(ptr_), size_);
    path_ = std::move(other.path_);
    ptr_ = std::exchange(other.ptr_, nullptr);
    size_ = std::exchange(other.size_, 0);
  }
  return *this;
}

mapped_file::~mapped_file() {
  if (ptr_ != nullptr && size_ != 0) ::munmap(const_cast<char*>(ptr_), size_);
}

void drop_pages(const char* base, std::size_t size, std::size_t begin, std::size_t end,
                std::size_t granule) noexcept {
  if (base == nullptr || size == 0) return;
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const auto unit = std::max(granule, page);
  const auto at = reinterpret_cast<std::uintptr_t>(base);  // NOLINT: page arithmetic
  // The mapping holds whole pages: from the page of byte 0 to the page of byte size - 1.
  const std::uintptr_t map_lo = at / page * page;
  const std::uintptr_t map_hi = (at + size + page - 1) / page * page;
  const std::uintptr_t lo = std::max(map_lo, (at + begin) / unit * unit);
  const std::uintptr_t hi = std::min(map_hi, (at + std::min(end, size) + unit - 1) / unit * unit);
  if (hi > lo)
    ::madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_DONTNEED);  // NOLINT: madvise takes void*
}

void mapped_file::release(std::size_t begin, std::size_t end, std::size_t granule) const noexcept {
  drop_pages(ptr_, size_, begin, end, granule);
}

void mapping_samples::release(std::size_t begin, std::size_t end) const noexcept {
  if (count_ < keep_resident_samples) return;
  // cppcheck-suppress invalidPointerCast ; the samples' bytes
  const auto* bytes = reinterpret_cast<const char*>(data_);  // NOLINT: byte view
  drop_pages(bytes, count_ * sizeof(double), begin * sizeof(double), end * sizeof(double),
             std::size_t{1} << 16);
}

result<mapped_file> mapped_file::open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return io_error(path, std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int e = errno;
    ::close(fd);
    return io_error(path, std::strerror(e));
  }
  if (S_ISDIR(st.st_mode)) {
    ::close(fd);
    return io_error(path, "is a directory, not a file");
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    return io_error(path, "not a regular file");
  }
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size == 0) {
    ::close(fd);
    return mapped_file(path, nullptr, 0);
  }
  void* p = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
  const int e = errno;
  ::close(fd);
  if (p == MAP_FAILED) return io_error(path, std::strerror(e));
  ::madvise(p, size, MADV_SEQUENTIAL);
  return mapped_file(path, static_cast<const char*>(p), size);
}

}  // namespace gyroflip::io
