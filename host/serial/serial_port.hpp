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

/// A port's lock, held by one gyroflip recorder for its whole session, also while the port is
/// gone (an unplugged adapter, an emulator's pty that comes back): a second recorder is refused
/// at once even then, and cannot take the line while the first one reconnects. An advisory lock
/// (flock) on a file in /run/lock (else /var/lock, else /tmp), whose content is the holder's
/// process id; the kernel releases it when the holder ends, however it ends (the file stays:
/// removing a lock file races with the next taker). docs/RECORDER.md.
class port_lock {
 public:
  /// The lock of the name `path` as given, made absolute (a symbolic link and its target are
  /// two names: see `device_key`). Refused with "in use by another program (a gyroflip record,
  /// process N)".
  [[nodiscard]] static result<port_lock> of_name(const std::string& path);
  /// The key of the device `path` names now (its device number, so every name of it), or of
  /// the file when it is no device; for `take`.
  [[nodiscard]] static result<std::string> device_key(const std::string& path);
  /// The lock of `key`; `path` names the port in the refusal.
  [[nodiscard]] static result<port_lock> take(const std::string& key, const std::string& path);
  port_lock(port_lock&& o) noexcept;
  port_lock& operator=(port_lock&& o) noexcept;
  port_lock(const port_lock&) = delete;
  port_lock& operator=(const port_lock&) = delete;
  ~port_lock();
  /// What the lock is on (a name, or `device MAJOR:MINOR`).
  [[nodiscard]] const std::string& key() const noexcept { return key_; }

 private:
  port_lock(int fd, std::string key) : fd_(fd), key_(std::move(key)) {}
  int fd_ = -1;
  std::string key_;
};

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
