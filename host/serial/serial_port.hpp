/// \file
/// \brief The recorder's end of the link: a serial device (a USB-serial adapter, a pty) opened
/// with standalone Asio (STACK.md section 1: libserialport cannot open ptys), raw 8N1 at a given
/// baud rate, no flow control, reads and writes with timeouts. Every error is returned, naming
/// the device; none is thrown. Asio stays out of this header.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "gyroflip/core/result.hpp"

namespace gyroflip::host {

class serial_port {
 public:
  /// Opens `path` raw 8N1, no flow control, at `baud` b/s (a pty accepts and ignores it), held
  /// exclusively: a port another recorder holds is refused ("in use"), as is any open of it by
  /// another program while this one is open (TIOCEXCL).
  [[nodiscard]] static result<serial_port> open(const std::string& path,
                                                std::uint32_t baud = 115200);
  serial_port(serial_port&&) noexcept;
  serial_port& operator=(serial_port&&) noexcept;
  serial_port(const serial_port&) = delete;
  serial_port& operator=(const serial_port&) = delete;
  ~serial_port();

  [[nodiscard]] const std::string& path() const noexcept;
  /// Reads what has arrived, up to `cap` bytes, waiting at most `timeout_ms` for the first one:
  /// 0 on timeout. An error means the line is gone (end of file, an unplugged adapter: EIO).
  [[nodiscard]] result<std::size_t> read(std::uint8_t* out, std::size_t cap, int timeout_ms);
  /// Writes all `n` bytes within `timeout_ms`, or fails.
  [[nodiscard]] status write(const std::uint8_t* p, std::size_t n, int timeout_ms);

 private:
  struct impl;
  explicit serial_port(std::unique_ptr<impl> p) noexcept;
  std::unique_ptr<impl> p_;
};

}  // namespace gyroflip::host
