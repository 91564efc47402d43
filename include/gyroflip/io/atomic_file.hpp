/// \file
/// \brief Output files that never replace what they should write into, never leave a partial
/// file, and never overwrite an input of the same run (docs/cli.md, "Output files").
///
/// - A regular file (or a path that does not exist yet) is written to a temporary file in the
///   directory of the *real* target (symlinks followed, so a symlink stays a symlink and its
///   target gets the data), flushed, fsync'ed and closed, then renamed over the target, and the
///   directory is fsync'ed. An existing target keeps its permission bits.
/// - A character device, FIFO or socket (`/dev/null`, a named pipe, a tty) is written straight
///   through: no temporary, no rename (a rename would replace the device or pipe by a file).
/// - `-` is standard output.
/// A run killed by SIGINT, SIGTERM or SIGHUP removes its temporaries when the program calls
/// `remove_temporary_files()` from its handler (the CLI does, apps/gyroflip/main.cpp).
#pragma once

#include <cstdio>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "gyroflip/core/result.hpp"

namespace gyroflip::io {

/// An output that appears under its final name only when committed.
class atomic_file {
 public:
  /// Opens the temporary (regular files) or the target itself (devices, FIFOs). Errors: the
  /// target is a directory, its directory is missing or not writable, a symlink loop.
  [[nodiscard]] static result<atomic_file> create(std::string path);

  atomic_file(atomic_file&& other) noexcept;
  atomic_file& operator=(atomic_file&&) = delete;
  atomic_file(const atomic_file&) = delete;
  atomic_file& operator=(const atomic_file&) = delete;
  /// Removes the temporary of an output that was not committed (error paths, exceptions).
  ~atomic_file();

  /// The stream to write to (stdout for `-`).
  [[nodiscard]] std::FILE* stream() const noexcept { return file_; }
  /// Appends `text`; write errors surface at `commit()` (or `prepare()`).
  void write(std::string_view text) const;

  /// Flushes, fsyncs and closes, then renames into place and fsyncs the directory. Errors:
  /// write, fsync or rename failed (disk full, ...); the temporary is removed then.
  [[nodiscard]] status commit();

  /// First half of `commit`: all data on disk under the temporary name, the file closed.
  [[nodiscard]] status prepare();
  /// Second half: the rename and the directory fsync (after a successful `prepare`).
  [[nodiscard]] status publish();

  /// The path the user gave.
  [[nodiscard]] const std::string& path() const noexcept { return path_; }

 private:
  enum class kind { regular, stream, standard_output };
  atomic_file(std::string path, std::string target, std::string temp, std::FILE* f, kind k,
              int slot) noexcept;
  void discard() noexcept;
  std::string path_;
  std::string target_;  // the real file (symlinks resolved) the rename replaces
  std::string temp_;    // empty unless kind::regular
  std::FILE* file_ = nullptr;
  kind kind_ = kind::regular;
  int slot_ = -1;  // entry in the registry of temporaries (signal clean-up)
  bool prepared_ = false;
};

/// Commits several outputs of one run as one: every output is prepared (written, fsync'ed,
/// closed) before any is renamed, so a failure in any (disk full on the second file) leaves
/// none of them committed. Errors: the first failure.
[[nodiscard]] status commit_all(std::initializer_list<atomic_file*> outputs);

/// Writes `text` to `path` atomically (convenience for small outputs such as JSON).
[[nodiscard]] status write_file_atomically(const std::string& path, std::string_view text);

/// The file (or folder) a write to `path` lands in: symlinks followed one by one, the target of a
/// dangling link being the file to create (as the shell's `>` does). Errors: a loop.
[[nodiscard]] result<std::string> real_target(const std::string& path);

/// The descriptor a path names that this process already has open: /dev/stdout (1),
/// /dev/stderr (2), /dev/fd/N and /proc/self/fd/N (N). Such an output is written straight into
/// a duplicate of that descriptor, where the shell's redirection put it (`>> log` appends), never
/// re-opened (which would truncate a file behind it, or fail for a pipe).
[[nodiscard]] std::optional<int> open_descriptor(const std::string& path);

/// A stream writing into the descriptor `path` names (open_descriptor), or nothing when it names
/// none. Errors: a descriptor that is not open for writing.
[[nodiscard]] result<std::FILE*> descriptor_stream(const std::string& path);

/// Checks, before a run does any work, that none of its `outputs` is one of its `inputs` (same
/// file: same device and inode, so `./a.csv`, `a.csv`, a symlink to it and a hard link all
/// count; an input `FILE.h5:/dataset` is the file FILE.h5, io::series_file) and that no two outputs
/// name the same file (same file, or the same resolved path for files that do not exist yet).
/// Devices and FIFOs may be named twice; `-` only once. Empty names are skipped. Errors: `OUT: ...`
/// naming both files (bad input).
[[nodiscard]] status check_outputs(std::span<const std::string> inputs,
                                   std::span<const std::string> outputs);

/// Checks that no file is among `inputs` twice, by any name (same device and inode): pooling a
/// recording twice would shrink its standard error by sqrt(2) for nothing. Errors: `FILE: ...`
/// naming both spellings (bad input).
[[nodiscard]] status check_distinct_inputs(std::span<const std::string> inputs);

/// A private folder for a run's work, `DIR/.NAME.gyroflip-tmp.*` (mode 0700), removed with all it
/// holds when the object goes, or by remove_temporary_files() on a signal; registered for that
/// before it is created, so no signal leaves it behind. A report is built in one beside its
/// target and renamed into place (then `keep()`), a figure is drawn in one.
class temporary_folder {
 public:
  /// Errors: DIR is missing or not writable.
  [[nodiscard]] static result<temporary_folder> create(const std::string& dir,
                                                       const std::string& name);
  temporary_folder(temporary_folder&& other) noexcept;
  temporary_folder& operator=(temporary_folder&&) = delete;
  temporary_folder(const temporary_folder&) = delete;
  temporary_folder& operator=(const temporary_folder&) = delete;
  /// Removes the folder and everything in it (unless kept).
  ~temporary_folder();
  [[nodiscard]] const std::string& path() const noexcept { return path_; }
  /// Forgets the folder: it is no longer removed (it was renamed into place).
  void keep() noexcept;

 private:
  temporary_folder(std::string path, int slot) noexcept;
  std::string path_;
  int slot_ = -1;
};

/// Removes every temporary file not yet committed and every temporary folder with what it
/// holds. Async-signal-safe (system calls only: unlink, getdents64, unlinkat): for
/// SIGINT/SIGTERM/SIGHUP handlers, before the process dies.
void remove_temporary_files() noexcept;

}  // namespace gyroflip::io
