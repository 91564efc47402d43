// The -o rules (issue 13 item 2): outputs write into devices, FIFOs and symlink targets without
// replacing them, never overwrite an input of the run, commit all or none, and leave no
// temporary file when the run fails or is killed. Each test failed on the main of 2026-11-22.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "support/run_cli.hpp"
#include "support/series_files.hpp"
#include "support/synth.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> simulate(const std::string& out, double duration_s = 60.0) {
  return {"simulate", "--sensor", "hz1-90-100a", "--duration", std::to_string(duration_s),
          "-o",       out};
}

// `n` samples of white noise (sd `sd`, fixed seed).
std::vector<double> white_noise(std::size_t n, double sd, std::uint64_t seed) {
  normal_source g(seed);
  std::vector<double> y(n);
  for (auto& v : y) v = sd * g();
  return y;
}

// Names in `dir` other than `keep` (temporaries left behind show here).
std::vector<std::string> stray_files(const temp_dir& d, const std::vector<std::string>& keep) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(d.path())) {
    const auto name = e.path().filename().string();
    if (std::find(keep.begin(), keep.end(), name) == keep.end()) out.push_back(name);
  }
  return out;
}

TEST(CliOutput, DevNullStaysACharacterDevice) {
  if (::geteuid() != 0) GTEST_SKIP() << "only root can replace /dev/null (the defect)";
  const auto r = run_cli(simulate("/dev/null"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
}

TEST(CliOutput, FifoGetsTheBytesAndStaysAFifo) {
  temp_dir d;
  const auto fifo = d.file("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto reader = std::async(std::launch::async, [&] { return read_text(fifo); });
  const auto r = run_cli(simulate(fifo));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string got = reader.get();
  EXPECT_NE(got.find("time_s,angle_deg,rate_dps"), std::string::npos);
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_EQ(stray_files(d, {"pipe"}), std::vector<std::string>{});
}

// An output named by a descriptor the process has (/dev/stdout, /dev/fd/N) goes where the
// shell's redirection put it: `>> log` appends (it replaced the log: the link was followed to
// the file and a temporary renamed over it), a pipe gets the bytes (it failed: "pipe:[N]" was
// taken for a file name). Also emulate --log.
TEST(CliOutput, DescriptorOutputsGoWhereTheShellPutThem) {
  temp_dir d;
  const std::string exe = GYROFLIP_EXE;
  const std::string log = d.file("log.txt");
  write_text(log, "line1 of my log\n");
  auto r = run_program(
      {"sh", "-c",
       exe + " simulate --sensor hz1-90-100a --duration 30 -o /dev/stdout >> " + log + " && " +
           exe + " simulate --sensor hz1-90-100a --duration 30 -o /dev/fd/3 3>> " + log});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string got = read_text(log);
  EXPECT_EQ(got.rfind("line1 of my log\n", 0), 0u) << got.substr(0, 200);
  const auto first = got.find("time_s,angle_deg,rate_dps");
  ASSERT_NE(first, std::string::npos);
  EXPECT_NE(got.find("time_s,angle_deg,rate_dps", first + 1), std::string::npos);  // appended
  r = run_program({"sh", "-c",
                   exe + " simulate --sensor hz1-90-100a --duration 30 -o /dev/stdout | head -c "
                         "100000 | grep -c time_s,angle_deg"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "1\n") << r.err;
  const std::string session = d.file("session.log");
  write_text(session, "session line 1\n");
  r = run_program(
      {"sh", "-c",
       exe + " emulate --pty --speed max --duration 2 --log /dev/stdout >> " + session});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string s = read_text(session);
  EXPECT_EQ(s.rfind("session line 1\n", 0), 0u) << s.substr(0, 200);
  EXPECT_NE(s.find("seq,cycle,position"), std::string::npos);
  // A dangling link of the user's (to an unmounted disk) is not taken for an old emulator's.
  const std::string link = d.file("rig");
  ASSERT_EQ(::symlink("/media/not-mounted/calibration", link.c_str()), 0);
  r = run_cli({"emulate", "--pty", "--link", link, "--speed", "max", "--duration", "1"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(fs::read_symlink(link), "/media/not-mounted/calibration");
  EXPECT_EQ(stray_files(d, {"log.txt", "session.log", "rig"}), std::vector<std::string>{});
}

TEST(CliOutput, SymlinkStaysAndItsTargetIsWritten) {
  temp_dir d;
  write_text(d.file("target.csv"), "old\n");
  fs::create_symlink("target.csv", d.file("link.csv"));
  ASSERT_EQ(run_cli(simulate(d.file("link.csv"))).exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(d.file("link.csv")));
  EXPECT_NE(read_text(d.file("target.csv")).find("time_s,angle_deg"), std::string::npos);
  // A dangling link: the file it names is created (as the shell's `>` does).
  fs::create_symlink("new.csv", d.file("dangling.csv"));
  ASSERT_EQ(run_cli(simulate(d.file("dangling.csv"))).exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(d.file("dangling.csv")));
  EXPECT_TRUE(fs::is_regular_file(d.file("new.csv")));
}

TEST(CliOutput, ExistingFileKeepsItsPermissions) {
  temp_dir d;
  write_text(d.file("private.csv"), "old\n");
  ASSERT_EQ(::chmod(d.file("private.csv").c_str(), 0600), 0);
  ASSERT_EQ(run_cli(simulate(d.file("private.csv"))).exit_code, 0);
  struct stat st {};
  ASSERT_EQ(::stat(d.file("private.csv").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
}

TEST(CliOutput, AnInputIsNeverOverwritten) {
  temp_dir d;
  ASSERT_EQ(run_cli(simulate(d.file("rec.csv"), 600)).exit_code, 0);
  const std::string before = read_text(d.file("rec.csv"));
  fs::create_symlink("rec.csv", d.file("link.csv"));
  fs::create_hard_link(d.file("rec.csv"), d.file("hard.csv"));
  const std::string dotted = d.path() + "/./rec.csv";
  for (const auto& out : {d.file("rec.csv"), dotted, d.file("link.csv"), d.file("hard.csv")}) {
    const auto r = run_cli({"calibrate", d.file("rec.csv"), "-o", out});
    EXPECT_EQ(r.exit_code, 2) << out;
    EXPECT_NE(r.err.find("is an input of this run"), std::string::npos) << r.err;
    EXPECT_EQ(read_text(d.file("rec.csv")), before) << out;
  }
  const auto c =
      run_cli({"compensate", d.file("rec.csv"), "--delta-n", "0", "-o", d.file("hard.csv")});
  EXPECT_EQ(c.exit_code, 2);
  const auto a = run_cli({"adev", d.file("rec.csv"), "-o", d.file("link.csv")});
  EXPECT_EQ(a.exit_code, 2);
  EXPECT_EQ(read_text(d.file("rec.csv")), before);
  EXPECT_EQ(stray_files(d, {"rec.csv", "link.csv", "hard.csv"}), std::vector<std::string>{});
}

// Issue 21: `adev FILE.h5:/rate_dps -o FILE.h5` replaced the HDF5 input by a CSV (the identity
// check looked for a file named "FILE.h5:/rate_dps"); so did noise -o, noise --kalibr and an -o
// link pointing at the input. Each output option, by the file's name, a symlink and a hard link.
TEST(CliOutput, AnHdf5InputBehindItsDatasetNameIsNeverOverwritten) {
  temp_dir d;
  write_h5(d.file("run.h5"), "/rate_dps", white_noise(4000, 0.01, 21), 100.0);
  const std::string before = read_text(d.file("run.h5"));
  fs::create_symlink("run.h5", d.file("link.h5"));
  fs::create_hard_link(d.file("run.h5"), d.file("hard.h5"));
  const std::string in = d.file("run.h5") + ":/rate_dps";
  ASSERT_EQ(run_cli({"adev", in}).exit_code, 0);  // the input reads
  for (const auto& out : {d.file("run.h5"), d.file("link.h5"), d.file("hard.h5")}) {
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"adev", in, "-o", out}, {"noise", in, "-o", out}, {"noise", in, "--kalibr", out}}) {
      const auto r = run_cli(args);
      EXPECT_EQ(r.exit_code, 2) << args[0] << " " << args[2] << " " << out;
      EXPECT_NE(r.err.find("is an input of this run"), std::string::npos) << r.err;
      EXPECT_TRUE(read_text(d.file("run.h5")) == before)
          << args[0] << " " << args[2] << " " << out << ": the HDF5 input was replaced";
    }
  }
  EXPECT_EQ(stray_files(d, {"run.h5", "link.h5", "hard.h5"}), std::vector<std::string>{});
}

// A white-noise rate recording as CSV (400 rows), for plots.
std::string noise_csv() {
  std::string csv = "time_s,rate_dps\n";
  const auto y = white_noise(400, 0.01, 5);
  for (std::size_t i = 0; i < y.size(); ++i)
    csv += std::to_string(i) + "," + std::to_string(y[i]) + "\n";
  return csv;
}

// `adev --plot NAME.png` also writes NAME.gp and NAME_K.dat beside it (one per column): an input
// of that name must not be replaced by plot data (issue 21).
TEST(CliOutput, APlotsSideFilesNeverReplaceAnInput) {
  if (std::system("command -v gnuplot >/dev/null") != 0) GTEST_SKIP() << "no gnuplot";
  temp_dir d;
  const std::string csv = noise_csv();
  for (const char* name : {"plot_1.dat", "plot.gp"}) {
    write_text(d.file(name), csv);
    const auto r = run_cli({"adev", d.file(name), "--plot", d.file("plot.png")});
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.err;
    EXPECT_NE(r.err.find("is an input of this run"), std::string::npos) << r.err;
    EXPECT_EQ(read_text(d.file(name)), csv) << name;
    EXPECT_EQ(stray_files(d, {name}), std::vector<std::string>{});
    fs::remove(d.file(name));
  }
  write_text(d.file("in.csv"), csv);
  const auto ok = run_cli({"adev", d.file("in.csv"), "--plot", d.file("plot.png")});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_TRUE(exists(d.file("plot_1.dat")) && exists(d.file("plot.gp")));
}

// Nor a script or data file of the user's, or a script restyled since (the figure's script
// says "Restyle and run again with: gnuplot NAME.gp"): refused before any work, left as it was;
// a script and data gyroflip wrote and nobody changed are replaced (issue 21's review: `adev
// --plot allan.png` overwrote the user's allan.gp and allan_1.dat).
TEST(CliOutput, APlotsSideFilesOfTheUsersAreNeverReplaced) {
  if (std::system("command -v gnuplot >/dev/null") != 0) GTEST_SKIP() << "no gnuplot";
  temp_dir d;
  const std::string csv = noise_csv();
  write_text(d.file("in.csv"), csv);
  const std::vector<std::string> plot{"adev", d.file("in.csv"), "--plot", d.file("plot.png"),
                                      "-o",   d.file("out.csv")};
  for (const char* name : {"plot.gp", "plot_1.dat"}) {
    write_text(d.file(name), "# mine\n");
    const auto r = run_cli(plot);
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.err;
    EXPECT_NE(r.err.find(std::string(name) + ": exists and is not a figure file as gyroflip "
                                             "wrote it"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(read_text(d.file(name)), "# mine\n") << name;
    EXPECT_EQ(stray_files(d, {"in.csv", name}), std::vector<std::string>{}) << name;
    fs::remove(d.file(name));
  }
  // gyroflip's own files are replaced; restyled, the script is the user's.
  ASSERT_EQ(run_cli(plot).exit_code, 0);
  ASSERT_EQ(run_cli(plot).exit_code, 0);
  const std::string script = read_text(d.file("plot.gp")) + "# MY RESTYLE\n";
  write_text(d.file("plot.gp"), script);
  const auto restyled = run_cli(plot);
  EXPECT_EQ(restyled.exit_code, 2) << restyled.err;
  EXPECT_EQ(read_text(d.file("plot.gp")), script);
}

TEST(CliOutput, TwoOutputsNamingOneFileAreRefused) {
  temp_dir d;
  const auto r = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "60", "-o",
                          d.file("x.csv"), "--truth", d.file("x.csv")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(exists(d.file("x.csv")));
  // Devices may be named twice.
  EXPECT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "60", "-o", "/dev/null",
                     "--truth", "/dev/null"})
                .exit_code,
            0);
}

TEST(CliOutput, AFailingOutputCommitsNoneOfThem) {
  temp_dir d;
  const auto r = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "60", "-o",
                          d.file("rec.csv"), "--truth", "/dev/full"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/dev/full"), std::string::npos) << r.err;
  EXPECT_EQ(stray_files(d, {}), std::vector<std::string>{});  // no rec.csv, no temporary
  // An existing target is left as it was.
  write_text(d.file("rec.csv"), "keep\n");
  EXPECT_EQ(run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "60", "-o",
                     d.file("rec.csv"), "--truth", "/dev/full"})
                .exit_code,
            2);
  EXPECT_EQ(read_text(d.file("rec.csv")), "keep\n");
  EXPECT_EQ(stray_files(d, {"rec.csv"}), std::vector<std::string>{});
}

TEST(CliOutput, AKilledRunLeavesNoTemporaryAndNoTarget) {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    temp_dir d;
    const int pid = spawn_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "1e7", "--raw",
                               "-o", d.file("big.csv")});
    // Wait (at most 20 s) until the temporary exists: the run is then writing.
    bool writing = false;
    for (int i = 0; i < 2000 && !writing; ++i) {
      writing = !stray_files(d, {}).empty();
      if (!writing) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_TRUE(writing);
    ::kill(pid, sig);
    EXPECT_EQ(wait_cli(pid), 128 + sig);
    EXPECT_EQ(stray_files(d, {}), std::vector<std::string>{}) << "signal " << sig;
  }
}

// A temporary's name holds the process id and a count from 0; a file of that name left by a
// killed run whose id is reused now (touched here by the shell that then becomes gyroflip, with
// the same id) is skipped and kept (the old code failed: "out.csv: cannot write: File exists").
TEST(CliOutput, AStaleTemporaryOfAReusedProcessIdIsSkippedAndKept) {
  temp_dir d;
  const std::string stale = d.file(".out.csv.gyroflip-tmp.$$.");
  const std::string cmd =
      "cd '" + d.path() + "' && sh -c 'for k in 0 1 2; do echo stale > " + stale +
      "$k; done; exec \"$0\" simulate --sensor adxrs150 --duration 100 -o out.csv' '" +
      GYROFLIP_EXE + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_TRUE(exists(d.file("out.csv")));
  const auto left = stray_files(d, {"out.csv"});
  ASSERT_EQ(left.size(), 3u) << ::testing::PrintToString(left);
  for (const auto& name : left) {
    EXPECT_NE(name.find(".out.csv.gyroflip-tmp."), std::string::npos) << name;
    EXPECT_EQ(read_text(d.file(name)), "stale\n") << name;
  }
}

TEST(CliOutput, CommittedFileIsComplete) {
  // fsync itself cannot be observed from a test (it matters only across a power cut); what can
  // be checked is that the committed file is whole: the last row ends the run.
  temp_dir d;
  ASSERT_EQ(run_cli(simulate(d.file("rec.csv"), 120)).exit_code, 0);
  const std::string text = read_text(d.file("rec.csv"));
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(text, run_cli(simulate("-", 120)).out);
}

}  // namespace
}  // namespace gyroflip::test
