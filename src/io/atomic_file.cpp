/// \file
/// \brief Temporary-file-and-rename output (see atomic_file.hpp).
#include "gyroflip/io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::io {

// cppcheck-suppress passedByValue ; sink parameter, moved from
atomic_file::atomic_file(std::string path, std::string temp, std::FILE* f) noexcept
    : path_(std::move(path)), temp_(std::move(temp)), file_(f) {}

atomic_file::atomic_file(atomic_file&& other) noexcept
    : path_(std::move(other.path_)),
      temp_(std::move(other.temp_)),
      file_(std::exchange(other.file_, nullptr)) {}

result<atomic_file> atomic_file::create(std::string path) {
  if (path == "-") return atomic_file(std::move(path), {}, stdout);
  std::string temp = fmt::format("{}.tmp.{}", path, static_cast<long>(::getpid()));
  std::FILE* f = std::fopen(temp.c_str(), "wb");
  if (f == nullptr) return io_error(path, fmt::format("cannot write: {}", std::strerror(errno)));
  return atomic_file(std::move(path), std::move(temp), f);
}

atomic_file::~atomic_file() {
  if (file_ != nullptr && !temp_.empty()) {
    std::fclose(file_);
    std::remove(temp_.c_str());
  }
}

void atomic_file::write(std::string_view text) const {
  std::fwrite(text.data(), 1, text.size(), file_);
}

status atomic_file::commit() {
  if (temp_.empty()) {
    // EPIPE: the reader closed the pipe early (`| head`); that is the reader's choice, not a
    // failure.
    if (std::fflush(file_) != 0 && errno != EPIPE)
      return io_error("<stdout>", std::strerror(errno));
    return ok();
  }
  std::FILE* f = std::exchange(file_, nullptr);
  const bool failed = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || failed) {
    const int e = errno;
    std::remove(temp_.c_str());
    return io_error(path_, fmt::format("write failed: {}", std::strerror(e)));
  }
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    const int e = errno;
    std::remove(temp_.c_str());
    return io_error(path_, fmt::format("cannot rename into place: {}", std::strerror(e)));
  }
  return ok();
}

status write_file_atomically(const std::string& path, std::string_view text) {
  auto f = atomic_file::create(path);
  if (!f) return f.err();
  f->write(text);
  return f->commit();
}

}  // namespace gyroflip::io
