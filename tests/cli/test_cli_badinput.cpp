// Inputs that were silently wrong or expensive before issue 13 (reviewed 2026-11-22): each case
// failed on that day's main. Every one must give exit 2, a message naming the file (and its
// line/column or record where one exists) and no output file.
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

// Item 4: a 2 GB line without a newline was scanned whole (2.1 GB resident) before "line longer
// than 1 MiB". Now the reader looks 1 MiB + 1 byte ahead. The file is sparse (no disk cost);
// the run must stay far below the file's size: 200 MB allows the program's own ~10 MB ten
// times over and is a tenth of the old peak.
TEST(CliBadInput, HugeLineFailsWithinTheFirstMebibyte) {
  temp_dir d;
  const std::string path = d.file("huge.csv");
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  // Digits past the 64 KiB binary probe, then a hole (NUL bytes are ordinary line content
  // beyond the probe): one line of 2 GB.
  const std::string header = "time_s,angle_deg,rate_dps\n" + std::string(std::size_t{1} << 17, '1');
  ASSERT_EQ(::write(fd, header.data(), header.size()), static_cast<ssize_t>(header.size()));
  ASSERT_EQ(::ftruncate(fd, std::int64_t{2} << 30), 0);
  ::close(fd);
  for (const auto& cmd : std::vector<std::vector<std::string>>{
           {"compensate", path, "--delta-n", "0"}, {"adev", path}, {"calibrate", path}}) {
    const auto r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd[0] << ": " << r.err;
    EXPECT_NE(r.err.find(path + ":2"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("longer than 1 MiB"), std::string::npos) << r.err;
    EXPECT_LT(r.max_rss_kb, 200 * 1024) << cmd[0];
  }
}

}  // namespace
}  // namespace gyroflip::test
