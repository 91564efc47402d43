// Hostile input for the recording reader: seeded random corruptions of a valid recording
// (byte flips, inserted separators, NULs, truncation) must each end in either cycles or an
// error that names the file - never a crash, hang or sanitizer report (run under ASan in CI).
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "gyroflip/io/recording.hpp"
#include "gyroflip/method/calibration.hpp"
#include "gyroflip/workflow/recordings.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::io {
namespace {

std::string mutate(std::string s, std::mt19937_64& rng) {
  static constexpr char alphabet[] = {',', '\n', '\r', '\0', '#',    '-',   '.',
                                      'e', 'n',  ' ',  '9',  '\xEF', '\xFF'};
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits && !s.empty(); ++e) {
    const std::size_t at = rng() % s.size();
    switch (rng() % 5) {
      case 0:
        s[at] = static_cast<char>(rng() & 0xFF);
        break;
      case 1:
        s.insert(at, 1, alphabet[rng() % sizeof alphabet]);
        break;
      case 2:
        s.erase(at, 1 + rng() % 8);
        break;
      case 3:
        s.resize(at);
        break;
      default:
        s.insert(at, s.substr(rng() % s.size(), 1 + rng() % 40));
        break;
    }
  }
  return s;
}

TEST(RecordingMutations, EveryCorruptionEndsInCyclesOrALocatedError) {
  const std::string good =
      test::read_text(std::string(GYROFLIP_VECTORS_DIR) + "/demo/run_rate_table_20c.csv")
          .substr(0, 4000);
  ASSERT_FALSE(good.empty());
  test::temp_dir d;
  const std::string path = d.file("mutant.csv");
  std::mt19937_64 rng(2026);
  int errors = 0;
  for (int i = 0; i < 3000; ++i) {
    test::write_text(path, mutate(good, rng));
    for (auto p : {method::pairing::abba, method::pairing::simple}) {
      const auto r = workflow::read_cycles(path, p);
      if (r) {
        EXPECT_GE(r->cycles.size(), method::min_cycles);
      } else {
        ++errors;
        ASSERT_EQ(r.err().message.rfind(path, 0), 0u) << r.err().message;  // starts with FILE
      }
    }
  }
  EXPECT_GT(errors, 1000);  // the corruptions do hit the checks
}

}  // namespace
}  // namespace gyroflip::io
