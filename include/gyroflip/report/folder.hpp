/// \file
/// \brief A report folder (`gyroflip report`, `reproduce`, Python's `gyroflip.report` and
/// `gyroflip.reproduce`), built in a staging folder beside DIR and swapped into place at the end,
/// so that DIR is never half written and nothing of the user's is ever removed (docs/cli.md,
/// "report").
///
/// DIR may be new, an empty folder, or a folder that a report made and that holds nothing else:
/// a report lists everything it wrote in DIR/.gyroflip-report, and a folder with any entry not on
/// its list (a user's notes.txt, a symbolic link) or without the list is refused. A symbolic link
/// DIR is followed: the folder it names is made or replaced, the link stays. No input of the run
/// may lie inside DIR. The folder gets the permission bits of the folder it replaces, or those the
/// user's umask gives a new folder. The staging folder is removed on failure and on SIGINT,
/// SIGTERM or SIGHUP (io::temporary_folder).
#pragma once

#include <span>
#include <string>

#include <sys/types.h>

#include "gyroflip/core/result.hpp"
#include "gyroflip/io/atomic_file.hpp"

namespace gyroflip::report {

class report_folder {
 public:
  /// The name of the list of what a report wrote, in every report folder.
  static constexpr const char* list_name = ".gyroflip-report";

  /// Checks `out` and `inputs` (see the file comment) and makes the staging folder, with
  /// figures/ in it. Errors (bad input, exit 2): what is wrong with DIR, naming it.
  [[nodiscard]] static result<report_folder> make(const std::string& out,
                                                  std::span<const std::string> inputs);

  /// The staging folder to write the report into.
  [[nodiscard]] const std::string& path() const noexcept { return staging_.path(); }

  /// Writes the list of what is in the staging folder and puts the folder in DIR's place (an
  /// earlier report there is swapped out in one step and removed).
  [[nodiscard]] status publish(const std::string& made_by);

 private:
  report_folder(std::string out, std::string target, io::temporary_folder staging, mode_t mode);
  std::string out_;     // as given
  std::string target_;  // the folder itself, symbolic links followed
  io::temporary_folder staging_;
  mode_t mode_;
};

}  // namespace gyroflip::report
