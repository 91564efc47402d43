/// \file
/// \brief Shared by the fuzz targets: the input bytes as a file with a given extension (the readers
/// choose the format by extension and map files), on tmpfs when there is one, removed afterwards.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace gyroflip::fuzz {

class input_file {
 public:
  input_file(const std::uint8_t* data, std::size_t size, const char* extension) {
    const char* dir = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    path_ = std::string(dir) + "/gyroflip-fuzz-" + std::to_string(::getpid()) + extension;
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (f == nullptr) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
  }
  ~input_file() { std::remove(path_.c_str()); }
  input_file(const input_file&) = delete;
  input_file& operator=(const input_file&) = delete;
  [[nodiscard]] const std::string& path() const noexcept { return path_; }

 private:
  std::string path_;
};

/// The series targets' body: the bytes as a file of extension `ext` through io::read_series (a
/// sample rate given for binary formats), then the phase source over what it read, both kinds.
int fuzz_series(const std::uint8_t* data, std::size_t size, const char* ext);

}  // namespace gyroflip::fuzz
