/// \file
/// \brief Report folders built aside and swapped into place (folder.hpp).
#include "gyroflip/report/folder.hpp"

#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/report/page.hpp"

namespace gyroflip::report {

namespace {

namespace fs = std::filesystem;

// Every entry below `dir`, relative to it, sorted: folders with a trailing '/', symbolic links
// (never followed, never written by a report) marked so that no list entry matches them.
result<std::vector<std::string>> entries_of(const fs::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::string rel = it->path().lexically_relative(dir).generic_string();
    const auto type = it->symlink_status(ec).type();
    if (type == fs::file_type::directory) rel += '/';
    if (type == fs::file_type::symlink) rel += " (a symbolic link)";
    out.push_back(std::move(rel));
  }
  if (ec) return io_error(dir.string(), "cannot list it: " + ec.message());
  std::sort(out.begin(), out.end());
  return out;
}

// What a report's list says of a file: the size and SHA-256 it had when the report wrote it
// (line "SHA256 SIZE NAME"). Lists of a gyroflip before the checksums name files alone (no size,
// no checksum); folders are named alone, with a trailing '/'.
struct listed_file {
  std::optional<std::uintmax_t> size_bytes;
  std::string sha256;
};

std::map<std::string, listed_file> read_list(std::istream& in) {
  std::map<std::string, listed_file> out;
  const auto all_of = [](std::string_view text, auto pred) {
    return !text.empty() && std::all_of(text.begin(), text.end(), pred);
  };
  const auto hex = [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); };
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line.front() == '#') continue;
    const auto size_end = line.size() > 66 ? line.find(' ', 65) : std::string::npos;
    const std::string_view l = line;
    if (size_end != std::string::npos && line[64] == ' ' && all_of(l.substr(0, 64), hex) &&
        all_of(l.substr(65, size_end - 65), digit)) {
      out[line.substr(size_end + 1)] = {std::stoull(line.substr(65, size_end - 65)),
                                        line.substr(0, 64)};
      continue;
    }
    out[line] = {};
  }
  return out;
}

// The list's line for the entry `e` (as entries_of names it) of `dir`.
result<std::string> list_line(const fs::path& dir, const std::string& e) {
  if (e.back() == '/') return e;
  std::error_code ec;
  const auto size = fs::file_size(dir / e, ec);
  if (ec) return io_error((dir / e).string(), ec.message());
  auto sum = sha256_file((dir / e).string());
  if (!sum) return sum.err();
  return fmt::format("{} {} {}", *sum, size, e);
}

// Whether the existing folder `target` may be replaced: empty, or holding only what its report's
// list names, each file as the report wrote it (size and SHA-256). Errors name `out` and the
// first entry that is not the report's or was changed.
status check_replaceable(const fs::path& target, const std::string& out) {
  struct stat st {};
  if (::lstat(target.c_str(), &st) != 0) return ok();  // new
  if (!S_ISDIR(st.st_mode))
    return input_error({out}, "exists and is not a folder: give a new folder for the report");
  auto have = entries_of(target);
  if (!have) return have.err();
  if (have->empty()) return ok();
  std::ifstream list(target / report_folder::list_name);
  if (!list)
    return input_error({out}, fmt::format("is a folder that no gyroflip report made (it holds {}, "
                                          "and no {} list): not replaced; give a new or an empty "
                                          "folder",
                                          printable(have->front(), 200), report_folder::list_name));
  const auto listed = read_list(list);
  for (const auto& e : *have) {
    if (e == report_folder::list_name) continue;
    const auto it = listed.find(e);
    if (it == listed.end())
      return input_error({out}, fmt::format("holds {}, which its report did not write: not "
                                            "replaced (move it out, or give another folder)",
                                            printable(e, 200)));
    if (e.back() == '/') continue;
    if (!it->second.size_bytes)
      return input_error({out}, fmt::format("holds {}, listed by an older gyroflip that kept no "
                                            "checksums: whether it was edited cannot be told, so "
                                            "the folder is not replaced (give another folder, or "
                                            "move this one aside)",
                                            printable(e, 200)));
    std::error_code ec;
    const auto size = fs::file_size(target / e, ec);
    bool same = !ec && size == *it->second.size_bytes;
    if (same) {
      auto sum = sha256_file((target / e).string());
      if (!sum) return sum.err();
      same = *sum == it->second.sha256;
    }
    if (!same)
      return input_error({out}, fmt::format("holds {}, changed since its report wrote it: not "
                                            "replaced, so that the change is kept (give another "
                                            "folder, or move this one aside)",
                                            printable(e, 200)));
  }
  return ok();
}

// The permission bits a new folder gets from the user's umask.
mode_t umask_mode() {
  const mode_t mask = ::umask(0);  // reading the umask sets it: set it back at once
  ::umask(mask);
  return 0777 & ~mask;
}

}  // namespace

report_folder::report_folder(std::string out, std::string target, io::temporary_folder staging,
                             mode_t mode)
    : out_(std::move(out)), target_(std::move(target)), staging_(std::move(staging)), mode_(mode) {}

result<report_folder> report_folder::make(const std::string& out,
                                          std::span<const std::string> inputs) {
  // A symbolic link is followed: its target is the folder (made if the link dangles). A trailing
  // slash (a shell's completion of a folder name) names the same folder.
  std::string given = out;
  while (given.size() > 1 && given.back() == '/') given.pop_back();
  auto real = io::real_target(given);
  if (!real) return real.err();
  const fs::path target = fs::absolute(*real).lexically_normal();
  if (target.filename().empty() || target == target.root_path())
    return input_error({out}, "is not a folder a report can be made in");
  // No input inside: the folder is replaced as a whole.
  std::error_code ec;
  const fs::path inside = fs::weakly_canonical(target, ec);
  for (const auto& in : inputs) {
    if (in.empty() || ec) continue;
    std::error_code e;
    const fs::path file = fs::weakly_canonical(in, e);
    if (e) continue;
    const auto rel = file.lexically_relative(inside);
    if (!rel.empty() && *rel.begin() != ".." && rel != ".")
      return input_error({out}, fmt::format("holds {}, an input of this run: a report replaces its "
                                            "folder as a whole; give another folder",
                                            printable(in, 200)));
  }
  if (auto s = check_replaceable(target, out); !s) return s.err();
  struct stat st {};
  const bool replacing = ::stat(target.c_str(), &st) == 0;
  mode_t mode = replacing ? static_cast<mode_t>(st.st_mode & 07777) : umask_mode();
  auto staging =
      io::temporary_folder::create(target.parent_path().string(), target.filename().string());
  if (!staging) return staging.err();
  // The group: that of the folder replaced, with its setgid bit set at once, so that figures/
  // and every file take the group as they would in the folder itself (a shared folder stays
  // shared); a new folder gets what mkdir gives it (under a setgid parent: the parent's group
  // and the setgid bit, kept). A group the user may not give (EPERM) is left as it is.
  struct stat made {};
  if (::stat(staging->path().c_str(), &made) != 0)
    return io_error(out, fmt::format("cannot read its staging folder: {}", std::strerror(errno)));
  if (replacing) {
    if (made.st_gid != st.st_gid &&
        ::chown(staging->path().c_str(), static_cast<uid_t>(-1), st.st_gid) != 0 && errno != EPERM)
      return io_error(out, fmt::format("cannot give it its group: {}", std::strerror(errno)));
    if ((st.st_mode & S_ISGID) != 0 && ::chmod(staging->path().c_str(), 0700 | S_ISGID) != 0)
      return io_error(out, fmt::format("cannot set its permissions: {}", std::strerror(errno)));
  } else {
    mode |= made.st_mode & S_ISGID;
  }
  fs::create_directory(fs::path(staging->path()) / "figures", ec);
  if (ec) return io_error(out, ec.message());
  return report_folder(out, target.string(), std::move(*staging), mode);
}

namespace {

// Removes the earlier report at `dir` (checked: every entry its report's), entry by entry, deepest
// first, and then the folder: never a folder with anything in it, so that a file that appeared
// after the check stays (with the folders above it). Errors name `out` and where the earlier
// report is kept.
status remove_earlier(const std::string& dir, const std::string& out) {
  auto have = entries_of(dir);
  if (!have) return have.err();
  for (auto e = have->rbegin(); e != have->rend(); ++e) {
    const bool folder = e->back() == '/';
    const std::string path = dir + "/" + (folder ? e->substr(0, e->size() - 1) : *e);
    (void)(folder ? ::rmdir(path.c_str()) : ::unlink(path.c_str()));  // a failure: rmdir tells
  }
  if (::rmdir(dir.c_str()) != 0)
    return io_error(out, fmt::format("the report is in place; the earlier one could not be removed "
                                     "wholly ({}): what is left of it is in {}",
                                     std::strerror(errno), dir));
  return ok();
}

}  // namespace

status report_folder::publish(const std::string& made_by) {
  auto have = entries_of(staging_.path());
  if (!have) return have.err();
  std::string list = fmt::format(
      "# A report folder made by {}. A later report replaces this folder only while it holds\n"
      "# nothing but the entries below (and this list), each file unchanged. Files: SHA-256,\n"
      "# size in bytes, name; folders: name/.\n",
      made_by);
  for (const auto& e : *have) {
    auto line = list_line(staging_.path(), e);
    if (!line) return line.err();
    list += *line + "\n";
  }
  if (auto s = io::write_file_atomically(staging_.path() + "/" + list_name, list); !s) return s;
  if (::chmod(staging_.path().c_str(), mode_) != 0)
    return io_error(out_, fmt::format("cannot set its permissions: {}", std::strerror(errno)));
  struct stat st {};
  if (::lstat(target_.c_str(), &st) != 0) {
    // New: renamed into place, unless something appeared there meanwhile.
    if (::renameat2(AT_FDCWD, staging_.path().c_str(), AT_FDCWD, target_.c_str(),
                    RENAME_NOREPLACE) != 0 &&
        (errno != EINVAL || std::rename(staging_.path().c_str(), target_.c_str()) != 0))
      return io_error(out_,
                      fmt::format("cannot put the report in place: {}", std::strerror(errno)));
    staging_.keep();
    return ok();
  }
  // The earlier report was checked when the run began; the user may have added to it since.
  if (auto s = check_replaceable(target_, out_); !s) return s;
  // An earlier report: swapped with the new one in one step, so that DIR always holds a whole
  // report; the staging name then holds the earlier one. Checked again there (something may have
  // appeared between the check and the swap): if it is no longer only the report's, swapped back.
  const std::string staged = staging_.path();
  if (::renameat2(AT_FDCWD, staged.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
    if (auto s = check_replaceable(staged, out_); !s) {
      if (::renameat2(AT_FDCWD, staged.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0) {
        staging_.keep();  // the earlier folder stays where it is, with what appeared in it
        return error{s.err().code, fmt::format("{}; it could not be put back ({}) and is in {}",
                                               s.err().message, std::strerror(errno), staged)};
      }
      return s;  // the new report goes with `staging_`
    }
    // Removed entry by entry (never as a tree, by the destructor or a signal): a file that
    // appears now stays.
    staging_.keep();
    return remove_earlier(staged, out_);
  }
  if (errno != EINVAL && errno != ENOSYS)
    return io_error(out_, fmt::format("cannot put the report in place: {}", std::strerror(errno)));
  // A file system without the exchange: the earlier report moved aside first (into an empty
  // folder of our own, which a rename may replace), checked there, then the new one renamed in.
  const fs::path target(target_);
  auto old = io::temporary_folder::create(target.parent_path().string(),
                                          target.filename().string() + ".old");
  if (!old) return old.err();
  if (std::rename(target_.c_str(), old->path().c_str()) != 0)
    return io_error(out_, fmt::format("cannot put the report in place: {}", std::strerror(errno)));
  const std::string aside = old->path();
  old->keep();  // from now on removed entry by entry only
  status checked = check_replaceable(aside, out_);
  if (!checked || std::rename(staging_.path().c_str(), target_.c_str()) != 0) {
    const int e = errno;
    if (std::rename(aside.c_str(), target_.c_str()) != 0)  // the earlier folder back
      return io_error(out_, fmt::format("cannot put the report in place, nor the earlier folder "
                                        "back ({}): it is in {}",
                                        std::strerror(errno), aside));
    if (!checked) return checked;
    return io_error(out_, fmt::format("cannot put the report in place: {}", std::strerror(e)));
  }
  staging_.keep();
  return remove_earlier(aside, out_);
}

}  // namespace gyroflip::report
