/// \file
/// \brief Output files: temporary + fsync + rename for regular files, straight through for
/// devices and pipes, symlinks followed, inputs protected (see atomic_file.hpp).
#include "gyroflip/io/atomic_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <random>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/io/series.hpp"

namespace gyroflip::io {
namespace {

// The registry of live temporaries (files and folders), for the signal handler. This is the
// library's one piece of process-wide state besides the report module's helper programs: a
// handler can reach nothing else, and the temporaries are process-wide by nature (a SIGTERM kills
// every output at once). Fixed slots of fixed buffers, claimed with atomic flags, so that the
// handler reads only memory that is complete and never allocates.
constexpr std::size_t max_temporaries = 16;
struct temp_slot {
  std::atomic<bool> used{false};
  bool folder = false;  // removed with everything in it
  std::array<char, PATH_MAX> path{};
};
std::array<temp_slot, max_temporaries> registry;  // NOLINT: see above

int register_temporary(const std::string& path, bool folder = false) noexcept {
  if (path.size() >= PATH_MAX) return -1;
  for (std::size_t i = 0; i < registry.size(); ++i) {
    bool expected = false;
    // Claimed first, filled next, published last: the handler checks `path[0]`, so a slot
    // claimed but not yet filled (still all zero) is skipped.
    if (!registry[i].used.compare_exchange_strong(expected, true)) continue;
    registry[i].folder = folder;
    std::memcpy(registry[i].path.data() + 1, path.c_str() + 1, path.size());
    std::atomic_signal_fence(std::memory_order_release);
    registry[i].path[0] = path[0];
    return static_cast<int>(i);
  }
  return -1;  // more than max_temporaries outputs at once: no signal clean-up for this one
}

void unregister_temporary(int slot) noexcept {
  if (slot < 0) return;
  auto& s = registry[static_cast<std::size_t>(slot)];
  s.path[0] = '\0';
  std::atomic_signal_fence(std::memory_order_release);
  s.path.fill('\0');
  s.used.store(false);
}

std::string errno_text(int e) {
  return std::strerror(e);
}

std::string dir_of(const std::string& path) {
  const auto slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string base_of(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace

std::optional<int> open_descriptor(const std::string& path) {
  if (path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  for (const std::string_view prefix : {"/dev/fd/", "/proc/self/fd/"}) {
    if (!path.starts_with(prefix)) continue;
    const std::string_view digits = std::string_view(path).substr(prefix.size());
    int n = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
    if (ec == std::errc{} && end == digits.data() + digits.size() && n >= 0) return n;
  }
  return std::nullopt;
}

result<std::FILE*> descriptor_stream(const std::string& path) {
  const auto n = open_descriptor(path);
  if (!n) return static_cast<std::FILE*>(nullptr);
  const int flags = ::fcntl(*n, F_GETFL);
  if (flags < 0 || (flags & O_ACCMODE) == O_RDONLY)
    return io_error(path, fmt::format("descriptor {} is not open for writing", *n));
  const int fd = ::fcntl(*n, F_DUPFD_CLOEXEC, 3);
  if (fd < 0) return io_error(path, fmt::format("cannot write: {}", errno_text(errno)));
  std::FILE* f = ::fdopen(fd, "wb");
  if (f == nullptr) {
    const int e = errno;
    ::close(fd);
    return io_error(path, fmt::format("cannot write: {}", errno_text(e)));
  }
  return f;
}

result<std::string> real_target(const std::string& path) {
  std::string p = path;
  for (int hops = 0; hops < 40; ++hops) {
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return p;
    std::array<char, PATH_MAX> buf{};
    const ssize_t n = ::readlink(p.c_str(), buf.data(), buf.size() - 1);
    if (n < 0) return io_error(path, fmt::format("cannot read symlink: {}", errno_text(errno)));
    const std::string link(buf.data(), static_cast<std::size_t>(n));
    if (link.front() == '/') {
      p = link;
    } else {
      p = dir_of(p).append("/").append(link);
    }
  }
  return io_error(path, "too many levels of symbolic links");
}

namespace {

// An absolute spelling of the file `path` writes to, for comparing outputs that do not exist
// yet: the real directory plus the last component.
std::optional<std::string> resolved_path(const std::string& path) {
  auto target = real_target(path);
  if (!target) return std::nullopt;
  char* dir = ::realpath(dir_of(*target).c_str(), nullptr);
  if (dir == nullptr) return std::nullopt;
  std::string out = std::string(dir) + "/" + base_of(*target);
  std::free(dir);  // NOLINT: realpath's buffer
  return out;
}

status fsync_directory(const std::string& dir, const std::string& path) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0)
    return io_error(path, fmt::format("cannot open its directory: {}", errno_text(errno)));
  const int rc = ::fsync(fd);
  const int e = errno;
  ::close(fd);
  // Some file systems cannot sync a directory (EINVAL); the rename itself has happened.
  if (rc != 0 && e != EINVAL)
    return io_error(path, fmt::format("cannot sync its directory: {}", errno_text(e)));
  return ok();
}

}  // namespace

// cppcheck-suppress passedByValue ; sink parameters, moved from
atomic_file::atomic_file(std::string path, std::string target, std::string temp, std::FILE* f,
                         kind k, int slot) noexcept
    : path_(std::move(path)),
      target_(std::move(target)),
      temp_(std::move(temp)),
      file_(f),
      kind_(k),
      slot_(slot) {}

atomic_file::atomic_file(atomic_file&& other) noexcept
    : path_(std::move(other.path_)),
      target_(std::move(other.target_)),
      temp_(std::move(other.temp_)),
      file_(std::exchange(other.file_, nullptr)),
      kind_(other.kind_),
      slot_(std::exchange(other.slot_, -1)),
      prepared_(std::exchange(other.prepared_, false)) {}

result<atomic_file> atomic_file::create(std::string path) {
  if (path == "-") return atomic_file(std::move(path), {}, {}, stdout, kind::standard_output, -1);
  // /dev/stdout, /dev/fd/N: where the shell's redirection points (a pipe, `>> log`), written
  // through; following the link to a regular file and renaming over it would replace the file.
  auto through = descriptor_stream(path);
  if (!through) return through.err();
  if (*through != nullptr) return atomic_file(path, path, {}, *through, kind::stream, -1);
  auto target = real_target(path);
  if (!target) return target.err();
  struct stat st {};
  const bool exists = ::stat(target->c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) return io_error(path, "is a directory");
  if (exists && !S_ISREG(st.st_mode)) {
    // Devices, FIFOs, sockets: the data go straight in (a rename would replace them by a file).
    const int fd = ::open(target->c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) return io_error(path, fmt::format("cannot write: {}", errno_text(errno)));
    std::FILE* f = ::fdopen(fd, "wb");
    if (f == nullptr) {
      ::close(fd);
      return io_error(path, fmt::format("cannot write: {}", errno_text(errno)));
    }
    return atomic_file(std::move(path), std::move(*target), {}, f, kind::stream, -1);
  }
  // A hidden name in the target's directory (the rename must not cross file systems), unique
  // per process and output. A file of that name left by a killed process that had this process's
  // id (ids are reused) is skipped, and never removed: the next number is tried.
  static std::atomic<unsigned> counter{0};
  std::string temp;
  int slot = -1;
  int fd = -1;
  for (int attempt = 0; fd < 0; ++attempt) {
    if (attempt == 100)
      return io_error(path, "cannot write: every temporary name tried beside it exists");
    temp = fmt::format("{}/.{}.gyroflip-tmp.{}.{}", dir_of(*target), base_of(*target),
                       static_cast<long>(::getpid()), counter.fetch_add(1));
    struct stat taken {};
    if (::lstat(temp.c_str(), &taken) == 0) continue;  // not ours: never registered
    // Registered for removal on a signal before it exists: a signal between the two steps must
    // not leave it behind (a signal before the open finds nothing to remove; the name holds this
    // process's id and was free a moment ago, so no other process's file has it).
    slot = register_temporary(temp);
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) break;
    const int e = errno;
    unregister_temporary(slot);
    if (e != EEXIST) return io_error(path, fmt::format("cannot write: {}", errno_text(e)));
  }
  // An existing file keeps its permission bits (a user's 0600 recording stays private).
  if (exists) (void)::fchmod(fd, st.st_mode & 07777);
  std::FILE* f = ::fdopen(fd, "wb");
  if (f == nullptr) {
    const int e = errno;
    ::close(fd);
    ::unlink(temp.c_str());
    unregister_temporary(slot);
    return io_error(path, fmt::format("cannot write: {}", errno_text(e)));
  }
  return atomic_file(std::move(path), std::move(*target), std::move(temp), f, kind::regular, slot);
}

void atomic_file::discard() noexcept {
  if (file_ != nullptr && kind_ != kind::standard_output) std::fclose(file_);
  file_ = nullptr;
  if (kind_ == kind::regular && !temp_.empty()) {
    ::unlink(temp_.c_str());
    unregister_temporary(std::exchange(slot_, -1));
  }
}

atomic_file::~atomic_file() {
  discard();
}

void atomic_file::write(std::string_view text) const {
  if (file_ != nullptr) std::fwrite(text.data(), 1, text.size(), file_);
}

status atomic_file::prepare() {
  if (kind_ == kind::standard_output) {
    // EPIPE: the reader closed the pipe early (`| head`); that is the reader's choice, not a
    // failure.
    if (std::fflush(file_) != 0 && errno != EPIPE) return io_error("<stdout>", errno_text(errno));
    prepared_ = true;
    return ok();
  }
  std::FILE* f = std::exchange(file_, nullptr);
  int e = 0;
  if (std::fflush(f) != 0 || std::ferror(f) != 0) e = errno != 0 ? errno : EIO;
  // fsync: a regular file's data must be on disk before the rename makes it visible (else a
  // crash can leave an empty file under the final name). Devices and pipes may not support it.
  if (e == 0 && kind_ == kind::regular && ::fsync(::fileno(f)) != 0) e = errno;
  if (std::fclose(f) != 0 && e == 0) e = errno;
  if (e != 0) {
    discard();
    return io_error(path_, fmt::format("write failed: {}", errno_text(e)));
  }
  prepared_ = true;
  return ok();
}

status atomic_file::publish() {
  if (!prepared_) return io_error(path_, "not prepared");
  if (kind_ != kind::regular) return ok();
  if (std::rename(temp_.c_str(), target_.c_str()) != 0) {
    const int e = errno;
    discard();
    return io_error(path_, fmt::format("cannot rename into place: {}", errno_text(e)));
  }
  unregister_temporary(std::exchange(slot_, -1));
  temp_.clear();
  return fsync_directory(dir_of(target_), path_);
}

status atomic_file::commit() {
  if (auto s = prepare(); !s) return s;
  return publish();
}

status commit_all(std::initializer_list<atomic_file*> outputs) {
  for (atomic_file* f : outputs)
    if (f != nullptr)
      if (auto s = f->prepare(); !s) return s;  // the others' destructors remove theirs
  for (atomic_file* f : outputs)
    if (f != nullptr)
      if (auto s = f->publish(); !s) return s;
  return ok();
}

status write_file_atomically(const std::string& path, std::string_view text) {
  auto f = atomic_file::create(path);
  if (!f) return f.err();
  f->write(text);
  return f->commit();
}

status check_outputs(std::span<const std::string> inputs, std::span<const std::string> outputs) {
  struct seen {
    const std::string* name;
    dev_t dev;
    ino_t ino;
  };
  std::vector<seen> ins;
  for (const auto& in : inputs) {
    struct stat st {};
    // The file itself, through symlinks; for a series named `FILE.h5:/dataset`, FILE.h5.
    if (!in.empty() && in != "-" &&
        (::stat(in.c_str(), &st) == 0 || ::stat(series_file(in).c_str(), &st) == 0))
      ins.push_back({&in, st.st_dev, st.st_ino});
  }
  std::vector<seen> outs;
  std::vector<std::pair<const std::string*, std::string>> new_outs;  // not existing yet
  bool stdout_taken = false;
  for (const auto& out : outputs) {
    if (out.empty()) continue;
    if (out == "-") {
      if (stdout_taken) return usage_error("standard output ('-') is named for two outputs");
      stdout_taken = true;
      continue;
    }
    struct stat st {};
    if (::stat(out.c_str(), &st) == 0) {
      if (!S_ISREG(st.st_mode)) continue;  // devices and pipes: written through, never replaced
      for (const auto& in : ins)
        if (in.dev == st.st_dev && in.ino == st.st_ino)
          return input_error(
              {out},
              fmt::format("is an input of this run ({}); refusing to overwrite it", *in.name));
      for (const auto& o : outs)
        if (o.dev == st.st_dev && o.ino == st.st_ino)
          return input_error({out}, fmt::format("is the same file as output {}", *o.name));
      outs.push_back({&out, st.st_dev, st.st_ino});
      continue;
    }
    if (auto r = resolved_path(out)) {
      for (const auto& [name, path] : new_outs)
        if (path == *r)
          return input_error({out}, fmt::format("is the same file as output {}", *name));
      new_outs.emplace_back(&out, std::move(*r));
    }
  }
  return ok();
}

status check_distinct_inputs(std::span<const std::string> inputs) {
  std::vector<std::tuple<const std::string*, dev_t, ino_t>> seen;
  for (const auto& in : inputs) {
    struct stat st {};
    if (in.empty() || ::stat(in.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
    for (const auto& [name, dev, ino] : seen)
      if (dev == st.st_dev && ino == st.st_ino)
        return input_error({in}, fmt::format("is given twice (also as {}); each recording may be "
                                             "used once",
                                             printable(*name, 200)));
    seen.emplace_back(&in, st.st_dev, st.st_ino);
  }
  return ok();
}

namespace {

// Removes `name` in folder `dir_fd` and, for a folder, everything in it, with system calls only
// (async-signal-safe: no allocation, no stdio): entries are read with getdents64 into a buffer on
// the stack, at most `depth` folders deep. Best effort: what cannot be removed stays. True when
// `name` is gone.
bool remove_tree(int dir_fd, const char* name, int depth) noexcept {
  if (::unlinkat(dir_fd, name, 0) == 0 || errno == ENOENT) return true;
  if (depth == 0) return false;
  const int fd = ::openat(dir_fd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return false;
  // Passes until one removes nothing more: removing entries while reading may skip some.
  for (bool removed = true; removed;) {
    removed = false;
    ::lseek(fd, 0, SEEK_SET);
    alignas(8) char buf[2048];
    for (ssize_t n; (n = ::getdents64(fd, buf, sizeof buf)) > 0;) {
      for (ssize_t at = 0; at < n;) {
        const auto* e = reinterpret_cast<const dirent64*>(buf + at);  // NOLINT: kernel records
        at += e->d_reclen;
        const char* entry = e->d_name;
        if (entry[0] == '.' && (entry[1] == '\0' || (entry[1] == '.' && entry[2] == '\0')))
          continue;
        if (remove_tree(fd, entry, depth - 1)) removed = true;
      }
    }
  }
  ::close(fd);
  return ::unlinkat(dir_fd, name, AT_REMOVEDIR) == 0;
}

// Folders nest at most this deep in a temporary folder (a report's staging folder holds
// figures/ and, while Chromium prints, its profile, some 8 levels).
constexpr int max_folder_depth = 24;

}  // namespace

void remove_temporary_files() noexcept {
  for (auto& s : registry) {
    if (!s.used.load()) continue;
    std::atomic_signal_fence(std::memory_order_acquire);
    if (s.path[0] == '\0') continue;
    if (s.folder) {
      (void)remove_tree(AT_FDCWD, s.path.data(), max_folder_depth);
    } else {
      ::unlink(s.path.data());
    }
  }
}

// cppcheck-suppress passedByValue ; sink parameter, moved from
temporary_folder::temporary_folder(std::string path, int slot) noexcept
    : path_(std::move(path)), slot_(slot) {}

temporary_folder::temporary_folder(temporary_folder&& other) noexcept
    : path_(std::move(other.path_)), slot_(std::exchange(other.slot_, -1)) {
  other.path_.clear();
}

result<temporary_folder> temporary_folder::create(const std::string& dir, const std::string& name) {
  static std::atomic<unsigned> counter{0};
  std::random_device entropy;
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string path = fmt::format("{}/.{}.gyroflip-tmp.{}.{}{:08x}", dir, name,
                                   static_cast<long>(::getpid()), counter.fetch_add(1), entropy());
    // Registered before it exists, as a file temporary (atomic_file::create).
    const int slot = register_temporary(path, true);
    if (::mkdir(path.c_str(), 0700) == 0) return temporary_folder(std::move(path), slot);
    const int e = errno;
    unregister_temporary(slot);
    if (e != EEXIST)
      return io_error(dir, fmt::format("cannot create a folder in it: {}", errno_text(e)));
  }
  return io_error(dir, "cannot create a folder in it: every name tried exists");
}

temporary_folder::~temporary_folder() {
  if (path_.empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
  unregister_temporary(slot_);
}

void temporary_folder::keep() noexcept {
  unregister_temporary(std::exchange(slot_, -1));
  path_.clear();
}

}  // namespace gyroflip::io
