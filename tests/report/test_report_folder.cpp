// `report -o DIR` and `reproduce -o DIR` never destroy what the user has (issue 21): they
// replaced an existing folder wholesale (a user's notes.txt, an input of the same run inside it,
// a `.R.old` folder beside it, a symbolic link DIR all went), made folders 0700 whatever the
// umask, and a signal left the staging folder and a running gnuplot or Chromium behind. Each test
// failed on the code before the fix.
#include <dirent.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/report/folder.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using namespace gyroflip;
using test::read_text;
using test::run_cli;
using test::write_text;

bool have(const char* program) {
  return std::system((std::string("command -v ") + program + " >/dev/null 2>&1").c_str()) == 0;
}

// A short simulated recording in `dir` (run.csv), for reports.
std::string recording(const test::temp_dir& dir, const std::string& name = "run.csv") {
  const std::string path = dir.file(name);
  const auto r = run_cli(
      {"simulate", "--sensor", "hz1-90-100a", "--duration", "300", "--seed", "1", "-o", path});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return path;
}

// Names in `dir` starting with a dot: staging folders and temporaries left behind show here.
std::vector<std::string> hidden(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().front() == '.') out.push_back(e.path().filename());
  return out;
}

TEST(ReportFolder, NothingOfTheUsersIsReplaced) {
  if (!have("gnuplot")) GTEST_SKIP() << "gnuplot not installed";
  const test::temp_dir dir;
  const auto run = recording(dir);
  const std::string r = dir.file("R");
  ASSERT_EQ(run_cli({"report", run, "-o", r}).exit_code, 0);
  ASSERT_TRUE(fs::exists(r + "/.gyroflip-report"));
  const std::string page = read_text(r + "/index.html");
  // A file of the user's in the folder, or in figures/, or a link: refused, all left as they were.
  for (const std::string added : {"notes.txt", "figures/notes.txt", "link"}) {
    if (added == "link")
      fs::create_symlink(run, r + "/link");
    else
      write_text(r + "/" + added, "mine\n");
    const auto again = run_cli({"report", run, "-o", r});
    EXPECT_EQ(again.exit_code, 2) << added;
    EXPECT_NE(again.err.find("which its report did not write: not replaced"), std::string::npos)
        << again.err;
    EXPECT_TRUE(fs::exists(fs::symlink_status(r + "/" + added))) << added;
    EXPECT_EQ(read_text(r + "/index.html"), page);
    fs::remove(r + "/" + added);
  }
  // An input of the run inside the folder (the old code deleted it with the folder).
  fs::copy_file(run, r + "/input.csv");
  const auto inside = run_cli({"report", r + "/input.csv", "-o", r});
  EXPECT_EQ(inside.exit_code, 2);
  EXPECT_NE(inside.err.find("an input of this run"), std::string::npos) << inside.err;
  EXPECT_TRUE(fs::exists(r + "/input.csv"));
  fs::remove(r + "/input.csv");
  // A folder no report made (no list), even one that looks like a report, and a plain file.
  fs::create_directory(dir.file("mine"));
  write_text(dir.file("mine/index.html"), "my page\n");
  write_text(dir.file("mine/summary.json"), "{}\n");
  write_text(dir.file("file"), "mine\n");
  for (const auto& out : {dir.file("mine"), dir.file("file")}) {
    const auto refused = run_cli({"report", run, "-o", out});
    EXPECT_EQ(refused.exit_code, 2) << out;
  }
  EXPECT_EQ(read_text(dir.file("mine/index.html")), "my page\n");
  EXPECT_EQ(read_text(dir.file("file")), "mine\n");
  // A folder named like the old code's aside folder is someone else's.
  fs::create_directory(dir.file(".R.old"));
  write_text(dir.file(".R.old/keep.txt"), "mine\n");
  const auto replaced = run_cli({"report", run, "-o", r});
  ASSERT_EQ(replaced.exit_code, 0) << replaced.err;
  EXPECT_EQ(read_text(dir.file(".R.old/keep.txt")), "mine\n");
  EXPECT_EQ(hidden(dir.path()), std::vector<std::string>{".R.old"});
  // An empty folder is taken (named with a trailing slash, as a shell completes it); reproduce
  // follows the same rules (refused before it simulates).
  fs::create_directory(dir.file("empty"));
  EXPECT_EQ(run_cli({"report", run, "-o", dir.file("empty") + "/"}).exit_code, 0);
  EXPECT_TRUE(fs::exists(dir.file("empty/index.html")));
  write_text(r + "/notes.txt", "mine\n");
  const auto rep = run_cli({"reproduce", "--quick", "-o", r});
  EXPECT_EQ(rep.exit_code, 2);
  EXPECT_NE(rep.err.find("notes.txt, which its report did not write"), std::string::npos)
      << rep.err;
  EXPECT_EQ(read_text(r + "/notes.txt"), "mine\n");
}

// A report folder made through report_folder, as `report` makes it: index.html and
// figures/a.gp.
void make_report(const std::string& out, const std::string& page) {
  auto f = report::report_folder::make(out, {});
  ASSERT_TRUE(f) << f.err().message;
  write_text(f->path() + "/index.html", page);
  write_text(f->path() + "/figures/a.gp", "plot x\n");
  const auto s = f->publish("a test");
  ASSERT_TRUE(s) << s.err().message;
}

// What the user adds to the folder while a report runs (after the check at the start, before
// the swap at the end) stays, and the earlier report with it (the old code checked only at the
// start and removed the swapped-out folder with what had been added).
TEST(ReportFolder, WhatAppearsDuringTheRunIsKept) {
  const test::temp_dir dir;
  const std::string r = dir.file("R");
  make_report(r, "first\n");
  for (const std::string added : {"notes.txt", "figures/notes.txt"}) {
    auto f = report::report_folder::make(r, {});
    ASSERT_TRUE(f) << f.err().message;
    write_text(f->path() + "/index.html", "second\n");
    write_text(r + "/" + added, "mine\n");  // while the report runs
    const auto s = f->publish("a test");
    ASSERT_FALSE(s) << added;
    EXPECT_EQ(s.err().code, errc::bad_input);
    EXPECT_NE(s.err().message.find(added + ", which its report did not write"), std::string::npos)
        << s.err().message;
    EXPECT_EQ(read_text(r + "/" + added), "mine\n");
    EXPECT_EQ(read_text(r + "/index.html"), "first\n");
    fs::remove(r + "/" + added);
  }
  EXPECT_EQ(hidden(dir.path()), std::vector<std::string>{});
  make_report(r, "third\n");  // with nothing added: replaced
  EXPECT_EQ(read_text(r + "/index.html"), "third\n");
  EXPECT_EQ(hidden(dir.path()), std::vector<std::string>{});
}

// A file of the report edited by the user (a restyled figure script, as the script invites; a
// page changed at the same size) keeps its edit: the folder is refused (the old code's list held
// names only, and the re-run overwrote the edit). A list of an older gyroflip (names only) cannot
// tell: refused too.
TEST(ReportFolder, AnEditedFileOfTheReportIsKept) {
  const test::temp_dir dir;
  const std::string r = dir.file("R");
  make_report(r, "first\n");
  const struct {
    std::string file, text, why;
  } edits[] = {{"figures/a.gp", "plot x\n# MY RESTYLE\n", "changed since its report wrote it"},
               {"index.html", "fir5t\n", "changed since its report wrote it"}};
  for (const auto& e : edits) {
    const std::string before = read_text(r + "/" + e.file);
    write_text(r + "/" + e.file, e.text);
    const auto f = report::report_folder::make(r, {});
    ASSERT_FALSE(f) << e.file;
    EXPECT_EQ(f.err().code, errc::bad_input);
    EXPECT_NE(f.err().message.find(e.file + ", " + e.why), std::string::npos) << f.err().message;
    EXPECT_EQ(read_text(r + "/" + e.file), e.text);
    write_text(r + "/" + e.file, before);
  }
  EXPECT_EQ(hidden(dir.path()), std::vector<std::string>{});
  // Each file's line: SHA-256, size, name (`printf 'plot x\n' | sha256sum`).
  EXPECT_NE(read_text(r + "/.gyroflip-report")
                .find("\ne2dde7b97e9d69cb268019cd64f9ad8e245aa0000d01eb14e90855f8ec913fc7 7 "
                      "figures/a.gp\n"),
            std::string::npos)
      << read_text(r + "/.gyroflip-report");
  write_text(r + "/.gyroflip-report", "# an older list\nfigures/\nfigures/a.gp\nindex.html\n");
  const auto old = report::report_folder::make(r, {});
  ASSERT_FALSE(old);
  EXPECT_NE(old.err().message.find("kept no checksums"), std::string::npos) << old.err().message;
  EXPECT_EQ(read_text(r + "/index.html"), "first\n");
}

// A shared folder (another group, setgid) stays shared when a report replaces it, and a new
// report folder under a shared parent is shared as mkdir makes it: figures/ and the files take
// the group, folders the setgid bit (the old code gave the replaced folder the user's group and
// figures/ 0755 without setgid; a new folder lost the setgid bit mkdir gave it).
TEST(ReportFolder, AFoldersGroupAndSetgidBitAreKept) {
  const test::temp_dir dir;
  const gid_t other = ::getegid() + 4242;  // a group that is not the user's
  const std::string shared = dir.file("SG");
  ASSERT_EQ(::mkdir(shared.c_str(), 0775), 0);
  if (::chown(shared.c_str(), static_cast<uid_t>(-1), other) != 0)
    GTEST_SKIP() << "cannot give a folder another group here (not root)";
  ASSERT_EQ(::chmod(shared.c_str(), 02775), 0);
  make_report(shared, "first\n");   // replaces the empty folder
  make_report(shared, "second\n");  // replaces the report
  make_report(shared + "/new", "a new one\n");
  for (const std::string& path :
       {shared, shared + "/figures", shared + "/new", shared + "/new/figures"}) {
    struct stat st {};
    ASSERT_EQ(::stat(path.c_str(), &st), 0);
    EXPECT_EQ(st.st_gid, other) << path;
    EXPECT_NE(st.st_mode & S_ISGID, 0u) << path;
  }
  struct stat st {};
  ASSERT_EQ(::stat(shared.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 02775u);
  for (const std::string& path : {shared + "/index.html", shared + "/figures/a.gp",
                                  shared + "/.gyroflip-report", shared + "/new/index.html"}) {
    ASSERT_EQ(::stat(path.c_str(), &st), 0);
    EXPECT_EQ(st.st_gid, other) << path;
  }
}

TEST(ReportFolder, ASymbolicLinkIsFollowedAndStays) {
  if (!have("gnuplot")) GTEST_SKIP() << "gnuplot not installed";
  const test::temp_dir dir;
  const auto run = recording(dir);
  fs::create_directory(dir.file("store"));
  fs::create_symlink("store/R", dir.file("R"));  // dangling: the report makes store/R
  ASSERT_EQ(run_cli({"report", run, "-o", dir.file("R")}).exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(dir.file("R")));
  EXPECT_TRUE(fs::exists(dir.file("store/R/index.html")));
  const auto again = run_cli({"report", run, "-o", dir.file("R")});  // replaces store/R
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(fs::is_symlink(dir.file("R")));
  EXPECT_TRUE(fs::exists(dir.file("store/R/index.html")));
  EXPECT_TRUE(hidden(dir.path()).empty());
  EXPECT_TRUE(hidden(dir.file("store")).empty());
}

TEST(ReportFolder, PermissionsFollowTheUmaskOrTheReplacedFolder) {
  if (!have("gnuplot")) GTEST_SKIP() << "gnuplot not installed";
  const test::temp_dir dir;
  const auto run = recording(dir);
  const mode_t before = ::umask(027);  // the child inherits it
  const auto r = run_cli({"report", run, "-o", dir.file("R")});
  ::umask(before);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  struct stat st {};
  ASSERT_EQ(::stat(dir.file("R").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0750u);  // the old code: 0700 (mkdtemp)
  ASSERT_EQ(::stat(dir.file("R/index.html").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0640u);
  // A folder the user made private stays private when a report replaces it.
  ASSERT_EQ(::chmod(dir.file("R").c_str(), 0700), 0);
  ASSERT_EQ(run_cli({"report", run, "-o", dir.file("R")}).exit_code, 0);
  ASSERT_EQ(::stat(dir.file("R").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0700u);
}

// Whether a process is on its way out: a zombie, exiting (PF_EXITING in the flags, field 9 of
// /proc/PID/stat), or with SIGKILL pending.
bool dying(const std::string& pid, const std::string& stat, std::size_t close) {
  if (stat[close + 2] == 'Z' || stat[close + 2] == 'X') return true;
  std::istringstream fields(stat.substr(close + 2));
  std::string field;
  for (int k = 3; k <= 9 && fields >> field; ++k) {
  }
  if (std::strtoull(field.c_str(), nullptr, 10) & 0x4) return true;  // PF_EXITING
  std::istringstream status(read_text("/proc/" + pid + "/status"));
  for (std::string line; std::getline(status, line);)
    if ((line.rfind("SigPnd:", 0) == 0 || line.rfind("ShdPnd:", 0) == 0) &&
        std::strtoull(line.c_str() + 7, nullptr, 16) & (1ULL << (SIGKILL - 1)))
      return true;
  return false;
}

// The processes (not dying ones) whose command line or working folder names `dir`.
std::vector<std::string> processes_in(const std::string& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string pid = e.path().filename();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = read_text("/proc/" + pid + "/stat");
    const auto close = stat.rfind(')');
    if (close == std::string::npos || close + 2 >= stat.size() || dying(pid, stat, close)) continue;
    std::string cmd = read_text("/proc/" + pid + "/cmdline");
    for (auto& c : cmd)
      if (c == '\0') c = ' ';
    std::error_code ec;
    const std::string cwd = fs::read_symlink("/proc/" + pid + "/cwd", ec).string();
    if (cmd.find(dir) != std::string::npos || cwd.rfind(dir, 0) == 0)
      found.push_back(pid + " " + stat.substr(stat.find('('), close - stat.find('(') + 1));
  }
  return found;
}

// A child of `parent` named `comm` (gnuplot, chromium), waited for up to 60 s.
bool wait_for_child(int parent, const std::string& comm) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until) {
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string stat = read_text(e.path().string() + "/stat");
      const auto open = stat.find('('), close = stat.rfind(')');
      if (open == std::string::npos || close == std::string::npos) continue;
      if (stat.substr(open + 1, close - open - 1) != comm) continue;
      if (std::atoi(stat.c_str() + close + 4) == parent) return true;  // ") S PPID"
    }
    if (::kill(parent, 0) != 0) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  return false;
}

// SIGTERM while gnuplot draws a figure, and while Chromium prints the page: the report dies of it
// (128 + 15) and leaves neither its staging folder nor a helper (or a helper's child) running.
TEST(ReportFolder, ASignalLeavesNoStagingFolderAndNoHelperRunning) {
  for (const std::string helper : {"gnuplot", "chromium"}) {
    if (!have(helper.c_str())) continue;
    const test::temp_dir dir;
    const auto run = recording(dir);
    const int pid = test::spawn_cli({"report", run, "-o", dir.file("R")});
    const bool seen = wait_for_child(pid, helper);
    ::kill(pid, SIGTERM);
    const int status = test::wait_cli(pid);
    if (!seen) {
      ADD_FAILURE() << "no " << helper << " seen running under the report";
      continue;
    }
    EXPECT_EQ(status, 128 + SIGTERM) << helper;
    // Helpers are killed and waited for before the report dies; a helper's children (Chromium's)
    // have SIGKILL pending or are exiting by then. Checked at once: an orphan helper of the old
    // code finished its work on its own some 50-500 ms later.
    const auto left = processes_in(dir.path());
    EXPECT_EQ(left, std::vector<std::string>{}) << helper;
    EXPECT_EQ(hidden(dir.path()), std::vector<std::string>{}) << helper;
    EXPECT_FALSE(fs::exists(dir.file("R"))) << helper;
    for (const auto& p : left)
      ::kill(std::atoi(p.c_str()), SIGKILL);  // no orphan outlives the test
  }
}

}  // namespace
