// `gyroflip record` from the Cortex-M3 firmware image under QEMU, over QEMU's own pty (issue 9):
// the recorder talks to the real device code as to a rig, and `calibrate` reads what it stored.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "firmware/ports/cortex-m3-qemu/model_codes.hpp"
#include "gyroflip/rigdata/rig_run.hpp"
#include "support/pty_process.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace gyroflip;

TEST(RecordQemu, RecordsTheCortexM3ImageOverItsPtyAndCalibrateReadsIt) {
  const std::string elf = GYROFLIP_CM3_ELF;
  ASSERT_TRUE(std::filesystem::exists(elf)) << elf;
  test::temp_dir dir;
  const test::pty_process qemu(
      "qemu-system-arm -M mps2-an385 -icount shift=4,sleep=off -display none -monitor none -serial "
      "pty "
      "-semihosting-config enable=on,target=native -kernel " +
          elf,
      dir.path());
  const std::string& pty = qemu.pty();
  ASSERT_FALSE(pty.empty()) << qemu.output();
  const std::string gfr = dir.path() + "/run.gfr";
  // Quick dwells (16 conversions of 2 ms) so that a few seconds hold many cycles.
  const auto rec = test::run_cli({"record", "--port", pty, "--duration", "4", "--n-avg", "16",
                                  "--n-temp", "1", "--settle", "0.005", "--step-rate", "2000",
                                  "--start-rate", "1000", "--accel", "50000", "-o", gfr});
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  auto run = rigdata::read_rig_run(gfr);
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
