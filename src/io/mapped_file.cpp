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

void mapped_file::release(std::size_t begin, std::size_t end, std::size_t granule) const noexcept {
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  const auto unit = std::max(granule, page);
  const auto base = reinterpret_cast<std::uintptr_t>(ptr_);  // NOLINT: page arithmetic
  const std::uintptr_t map_end = (base + size_ + page - 1) / page * page;
  // Widened to whole units, but never beyond this mapping (base is page-aligned).
  const std::uintptr_t lo = std::max(base, (base + begin) / unit * unit);
  const std::uintptr_t hi =
      std::min(map_end, (base + std::min(end, size_) + unit - 1) / unit * unit);
  if (ptr_ != nullptr && hi > lo)
    ::madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_DONTNEED);  // NOLINT: madvise takes void*
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
