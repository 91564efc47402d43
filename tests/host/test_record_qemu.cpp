// `gyroflip record` from the Cortex-M3 firmware image under QEMU, over QEMU's own pty (issue 9):
// the recorder talks to the real device code as to a rig, and `calibrate` reads what it stored.
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "firmware/ports/cortex-m3-qemu/model_codes.hpp"
#include "host/recorder/rig_run.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace gyroflip;

TEST(RecordQemu, RecordsTheCortexM3ImageOverItsPtyAndCalibrateReadsIt) {
  const std::string elf = GYROFLIP_CM3_ELF;
  ASSERT_TRUE(std::filesystem::exists(elf)) << elf;
  test::temp_dir dir;
  const std::string out = dir.path() + "/qemu.out";
  const std::string cmd =
      "qemu-system-arm -M mps2-an385 -display none -monitor none -serial pty "
      "-semihosting-config enable=on,target=native -kernel " +
      elf + " >" + out + " 2>&1 & echo $! >" + dir.path() + "/qemu.pid";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::string pty;
  for (int i = 0; i < 250 && pty.empty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const std::string text = test::read_text(out);
    const auto at = text.find("/dev/pts/");
    if (at != std::string::npos && text.find(' ', at) != std::string::npos)
      pty = text.substr(at, text.find(' ', at) - at);
  }
  const int pid = std::stoi(test::read_text(dir.path() + "/qemu.pid"));
  ASSERT_FALSE(pty.empty()) << test::read_text(out);
  const std::string gfr = dir.path() + "/run.gfr";
  // Quick dwells (16 conversions of 2 ms) so that a few seconds hold many cycles.
  const auto rec = test::run_cli({"record", "--port", pty, "--duration", "4", "--n-avg", "16",
                                  "--n-temp", "1", "--settle", "0.005", "--step-rate", "2000",
                                  "--start-rate", "1000", "--accel", "50000", "-o", gfr});
  kill(pid, SIGTERM);
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  auto run = host::read_rig_run(gfr);
  ASSERT_TRUE(run) << run.err().message;
  EXPECT_EQ(run->info.serial, 0x51AB0001u);
  EXPECT_EQ(run->corrupt_frames + run->missing_frames, 0u);
  ASSERT_GE(run->dwells.size(), 20u);
  // Each dwell's sum is the firmware's model ADC's codes for its conversions.
  std::uint32_t index = 0;
  for (const auto& d : run->dwells) {
    std::int64_t sum = 0;
    for (std::uint32_t k = 0; k < 16; ++k)
      sum += fw::qemu::model_gyro_code(index + k, d.d.position == 1);
    EXPECT_EQ(d.d.code_sum, sum);
    index += 16;
  }
  const auto cal = test::run_cli({"calibrate", gfr, "--json"});
  EXPECT_EQ(cal.exit_code, 0) << cal.err;
  EXPECT_NE(cal.out.find("\"delta_n_dps\""), std::string::npos);
}

}  // namespace
