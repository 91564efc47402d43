/// \file
/// \brief The serial port on standalone Asio (serial_port.hpp). Timeouts follow STACK.md
/// section 1: an asynchronous read or write, `run_for` the timeout, then `cancel`.
#include "host/serial/serial_port.hpp"

#include <sys/file.h>
#include <sys/ioctl.h>
#include <termios.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <utility>

#include <asio/io_context.hpp>
#include <asio/read.hpp>
#include <asio/serial_port.hpp>
#include <asio/write.hpp>

#include "gyroflip/core/error.hpp"

namespace gyroflip::host {

struct serial_port::impl {
  explicit impl(std::string p) : path(std::move(p)) {}
  std::string path;
  asio::io_context io;
  asio::serial_port port{io};
};

namespace {

error port_error(const std::string& path, const char* op, const asio::error_code& ec) {
  return io_error(path, std::string(op) + ": " + ec.message());
}

// Runs the context until the pending operation completes or `timeout_ms` pass; on timeout the
// operation is cancelled and its handler run (with operation_aborted) before returning.
void run_with_timeout(asio::io_context& io, asio::serial_port& port, int timeout_ms,
                      const bool& done) {
  io.restart();
  io.run_for(std::chrono::milliseconds(timeout_ms));
  if (done) return;
  asio::error_code ignored;
  port.cancel(ignored);
  io.restart();
  io.run();
}

}  // namespace

result<serial_port> serial_port::open(const std::string& path, std::uint32_t baud) {
  auto p = std::make_unique<impl>(path);
  asio::error_code ec;
  p->port.open(path, ec);
  if (ec) return port_error(path, "cannot open", ec);
  // One program per port: an advisory lock that every gyroflip recorder takes (a second one is
  // refused at once, and the first loses nothing), and the terminal's exclusive mode, which
  // makes other programs' opens fail with EBUSY (root is exempt from it, not from the lock).
  const int fd = p->port.native_handle();
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno == EWOULDBLOCK)
      return runtime_error(path + ": in use by another program (another gyroflip record?)");
    return io_error(path, std::string("cannot lock: ") + std::strerror(errno));
  }
  (void)::ioctl(fd, TIOCEXCL);
  using sp = asio::serial_port;
  p->port.set_option(sp::baud_rate(baud), ec);
  if (!ec) p->port.set_option(sp::character_size(8), ec);
  if (!ec) p->port.set_option(sp::parity(sp::parity::none), ec);
  if (!ec) p->port.set_option(sp::stop_bits(sp::stop_bits::one), ec);
  if (!ec) p->port.set_option(sp::flow_control(sp::flow_control::none), ec);
  if (ec) return port_error(path, "cannot set 8N1 without flow control", ec);
  return serial_port(std::move(p));
}

serial_port::serial_port(std::unique_ptr<impl> p) noexcept : p_(std::move(p)) {}
serial_port::serial_port(serial_port&&) noexcept = default;
serial_port& serial_port::operator=(serial_port&&) noexcept = default;
serial_port::~serial_port() = default;

const std::string& serial_port::path() const noexcept {
  return p_->path;
}

result<std::size_t> serial_port::read(std::uint8_t* out, std::size_t cap, int timeout_ms) {
  bool done = false;
  asio::error_code ec;
  std::size_t got = 0;
  p_->port.async_read_some(asio::buffer(out, cap), [&](const asio::error_code& e, std::size_t n) {
    done = true;
    ec = e;
    got = n;
  });
  run_with_timeout(p_->io, p_->port, timeout_ms, done);
  if (ec == asio::error::operation_aborted) return std::size_t{0};
  if (ec) return port_error(p_->path, "read", ec);
  return got;
}

status serial_port::write(const std::uint8_t* p, std::size_t n, int timeout_ms) {
  bool done = false;
  asio::error_code ec;
  std::size_t put = 0;
  asio::async_write(p_->port, asio::buffer(p, n), [&](const asio::error_code& e, std::size_t k) {
    done = true;
    ec = e;
    put = k;
  });
  run_with_timeout(p_->io, p_->port, timeout_ms, done);
  if (ec == asio::error::operation_aborted || (!ec && put != n))
    return io_error(p_->path, "write timed out (the device does not take bytes)");
  if (ec) return port_error(p_->path, "write", ec);
  return ok();
}

}  // namespace gyroflip::host
