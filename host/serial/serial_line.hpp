/// \file
/// \brief A raw byte line to a serial device or the master end of a pseudo-terminal (POSIX
/// termios): 8N1, no flow control, no echo or line editing, reads and writes with timeouts.
/// Every error is returned, naming the device (docs/EMULATOR.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "gyroflip/core/result.hpp"

namespace gyroflip::host {

class serial_line {
 public:
  /// A new pseudo-terminal pair (posix_openpt): this line is the master; `peer_path()` names
  /// the slave, which a recorder opens like a serial port. The slave is made raw here and held
  /// open, so bytes are never echoed back and a reader that closes and reopens it loses nothing
  /// that was not yet written.
  [[nodiscard]] static result<serial_line> open_pty();
  /// An existing serial device (a USB-serial adapter, a socat pty), raw 8N1 at `baud` b/s.
  [[nodiscard]] static result<serial_line> open_device(const std::string& path,
                                                       std::uint32_t baud = 115200);
  serial_line(serial_line&& other) noexcept;
  serial_line& operator=(serial_line&& other) noexcept;
  serial_line(const serial_line&) = delete;
  serial_line& operator=(const serial_line&) = delete;
  ~serial_line();

  /// The device this line opened, or for a pty the slave's path.
  [[nodiscard]] const std::string& peer_path() const noexcept { return peer_; }
  /// Writes up to `n` bytes, waiting at most `timeout_ms` for room; returns how many were
  /// written (fewer on timeout).
  [[nodiscard]] result<std::size_t> write(const std::uint8_t* p, std::size_t n, int timeout_ms);
  /// Waits until the peer has taken what was written (a pty: the reader's input queue is empty;
  /// a device: the driver has sent it), at most `timeout_ms` for a pty. False when not drained.
  bool drain(int timeout_ms);
  /// Bytes written that the peer has not taken yet (a pty: the reader's input queue; a device:
  /// the driver's output queue); 0 when it cannot tell.
  [[nodiscard]] std::size_t unread() const noexcept;
  /// Reads what has arrived, up to `cap` bytes, waiting at most `timeout_ms` for the first one;
  /// 0 on timeout.
  [[nodiscard]] result<std::size_t> read(std::uint8_t* out, std::size_t cap, int timeout_ms);

 private:
  serial_line(int fd, int peer_fd, const std::string& peer)
      : fd_(fd), peer_fd_(peer_fd), peer_(peer) {}
  int fd_ = -1;
  int peer_fd_ = -1;  // a pty's slave, held open
  std::string peer_;
};

}  // namespace gyroflip::host
