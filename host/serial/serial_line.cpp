/// \file
/// \brief Raw serial lines and pseudo-terminals (serial_line.hpp).
#include "host/serial/serial_line.hpp"

#include <cerrno>
#include <cstring>
#include <utility>

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::host {

namespace {

error sys_error(const std::string& what_file, const char* op) {
  return io_error(what_file, std::string(op) + ": " + std::strerror(errno));
}

speed_t speed_of(std::uint32_t baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    default:
      return B0;
  }
}

// Raw 8N1, no flow control, reads return what is there (VMIN 0, VTIME 0).
bool make_raw(int fd, speed_t speed) {
  termios t{};
  if (tcgetattr(fd, &t) != 0) return false;
  cfmakeraw(&t);
  t.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS);
  t.c_cflag |= CS8 | CLOCAL | CREAD;
  t.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (speed != B0 && (cfsetispeed(&t, speed) != 0 || cfsetospeed(&t, speed) != 0)) return false;
  return tcsetattr(fd, TCSANOW, &t) == 0;
}

}  // namespace

result<serial_line> serial_line::open_pty() {
  const int m = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (m < 0) return sys_error("/dev/ptmx", "posix_openpt");
  char name[128] = {};
  if (grantpt(m) != 0 || unlockpt(m) != 0 || ptsname_r(m, name, sizeof name) != 0) {
    const error e = sys_error("/dev/ptmx", "grantpt/unlockpt/ptsname");
    close(m);
    return e;
  }
  const int s = open(name, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (s < 0 || !make_raw(s, B115200) || !make_raw(m, B115200)) {
    const error e = sys_error(name, "open raw");
    if (s >= 0) close(s);
    close(m);
    return e;
  }
  return serial_line(m, s, name);
}

result<serial_line> serial_line::open_device(const std::string& path, std::uint32_t baud) {
  const speed_t speed = speed_of(baud);
  if (speed == B0) return usage_error("baud rate: 9600, 19200, 38400, 57600, 115200 or 230400");
  const int fd = open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return sys_error(path, "open");
  if (!isatty(fd)) {
    close(fd);
    return io_error(path, "not a serial device (a terminal)");
  }
  if (!make_raw(fd, speed)) {
    const error e = sys_error(path, "set raw 8N1");
    close(fd);
    return e;
  }
  return serial_line(fd, -1, path);
}

serial_line::serial_line(serial_line&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      peer_fd_(std::exchange(other.peer_fd_, -1)),
      peer_(std::move(other.peer_)) {}

serial_line& serial_line::operator=(serial_line&& other) noexcept {
  if (this != &other) {
    serial_line gone(std::move(*this));
    fd_ = std::exchange(other.fd_, -1);
    peer_fd_ = std::exchange(other.peer_fd_, -1);
    peer_ = std::move(other.peer_);
  }
  return *this;
}

serial_line::~serial_line() {
  if (fd_ >= 0) close(fd_);
  if (peer_fd_ >= 0) close(peer_fd_);
}

result<std::size_t> serial_line::write(const std::uint8_t* p, std::size_t n, int timeout_ms) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(fd_, p + done, n - done);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
      continue;
    }
    if (w < 0 && errno != EAGAIN && errno != EINTR) return sys_error(peer_, "write");
    pollfd pf{fd_, POLLOUT, 0};
    const int r = poll(&pf, 1, timeout_ms);
    if (r == 0) break;
    if (r < 0 && errno != EINTR) return sys_error(peer_, "poll");
  }
  return done;
}

bool serial_line::drain(int timeout_ms) {
  if (peer_fd_ < 0) {
    // A serial device: the driver sends what it holds (tcdrain has no timeout; a UART finishes).
    return tcdrain(fd_) == 0;
  }
  // A pty: our slave descriptor shares the reader's input queue; wait until it is empty. Bytes
  // written to the master reach that queue a moment later (the kernel pushes its buffer from a
  // work queue), so one empty reading is not enough: three in a row, 10 ms apart.
  int empty_readings = 0;
  for (int waited = 0; empty_readings < 3; waited += 10) {
    int unread = 0;
    if (ioctl(peer_fd_, FIONREAD, &unread) != 0) return false;
    empty_readings = unread == 0 ? empty_readings + 1 : 0;
    if (empty_readings < 3 && waited >= timeout_ms) return false;
    if (empty_readings < 3) poll(nullptr, 0, 10);
  }
  return true;
}

std::size_t serial_line::unread() const noexcept {
  int n = 0;
  const int rc = peer_fd_ >= 0 ? ioctl(peer_fd_, FIONREAD, &n) : ioctl(fd_, TIOCOUTQ, &n);
  return rc == 0 && n > 0 ? static_cast<std::size_t>(n) : 0;
}

result<std::size_t> serial_line::read(std::uint8_t* out, std::size_t cap, int timeout_ms) {
  for (;;) {
    const ssize_t r = ::read(fd_, out, cap);
    if (r > 0) return static_cast<std::size_t>(r);
    // EIO on a pty master: no one has the slave open (our own copy keeps it open, so only a
    // device that vanished gets here).
    if (r == 0) return std::size_t{0};
    if (errno != EAGAIN && errno != EINTR) return sys_error(peer_, "read");
    pollfd pf{fd_, POLLIN, 0};
    const int p = poll(&pf, 1, timeout_ms);
    if (p == 0) return std::size_t{0};
    if (p < 0 && errno != EINTR) return sys_error(peer_, "poll");
    timeout_ms = 0;
  }
}

}  // namespace gyroflip::host
