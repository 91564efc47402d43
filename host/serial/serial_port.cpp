/// \file
/// \brief The serial port on standalone Asio (serial_port.hpp). Timeouts follow STACK.md
/// section 1: an asynchronous read or write, `run_for` the timeout, then `cancel`.
#include "host/serial/serial_port.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <termios.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <utility>

#include <fmt/format.h>

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

// Where lock files go: the first folder that exists and is writable (FHS: /run/lock, its
// older name /var/lock; /tmp where neither is).
std::string lock_folder() {
  for (const char* d : {"/run/lock", "/var/lock", "/tmp"})
    if (::access(d, W_OK | X_OK) == 0) return d;
  return "/tmp";
}

// A file name for `key`: the characters of a name kept, the others as %XX; a long key by its
// FNV-1a hash (a name is at most NAME_MAX bytes).
std::string lock_file_name(const std::string& key) {
  std::string out;
  for (const char ch : key) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) != 0 || c == '.' || c == '-' || c == '_')
      out += ch;
    else
      out += fmt::format("%{:02X}", c);
  }
  if (out.size() > 180) {
    std::uint64_t h = 14695981039346656037ULL;
    for (const char ch : key) h = (h ^ static_cast<unsigned char>(ch)) * 1099511628211ULL;
    out = fmt::format("hash-{:016x}", h);
  }
  return "gyroflip-record." + out + ".lock";
}

}  // namespace

result<port_lock> port_lock::take(const std::string& key, const std::string& path) {
  const std::string file = lock_folder() + "/" + lock_file_name(key);
  const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0666);
  if (fd < 0)
    return io_error(file, std::string("cannot open the port's lock: ") + std::strerror(errno));
  // Everyone may take the lock whoever made the file (a umask would take that right away).
  (void)::fchmod(fd, 0666);
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    char pid[32] = {};
    const ssize_t n = ::pread(fd, pid, sizeof pid - 1, 0);
    ::close(fd);
    if (e != EWOULDBLOCK) return io_error(file, std::string("cannot lock: ") + std::strerror(e));
    const std::string who = n > 0 ? fmt::format(", process {}", std::strtol(pid, nullptr, 10)) : "";
    return runtime_error(
        fmt::format("{}: in use by another program (a gyroflip record{}; {})", path, who, file));
  }
  const std::string me = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, me.data(), me.size(), 0) < 0) {
    // The lock holds without its note of who holds it.
  }
  return port_lock(fd, key);
}

result<port_lock> port_lock::of_name(const std::string& path) {
  std::error_code ec;
  auto abs = std::filesystem::absolute(path, ec);
  if (ec) abs = path;
  return take("name:" + abs.lexically_normal().string(), path);
}

result<std::string> port_lock::device_key(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return io_error(path, std::string("cannot open: ") + std::strerror(errno));
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode))
    return fmt::format("device:{}:{}", major(st.st_rdev), minor(st.st_rdev));
  return fmt::format("file:{}:{}", st.st_dev, st.st_ino);
}

port_lock::port_lock(port_lock&& o) noexcept
    : fd_(std::exchange(o.fd_, -1)), key_(std::move(o.key_)) {}
port_lock& port_lock::operator=(port_lock&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
    key_ = std::move(o.key_);
  }
  return *this;
}
port_lock::~port_lock() {
  if (fd_ >= 0) ::close(fd_);
}

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
