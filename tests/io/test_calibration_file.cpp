// The calibration file's runs and where they came from (schema gyroflip.calibration/2,
// docs/FORMATS.md): written and read back, refused when malformed, and absent in schema 1 files.
#include <string>

#include <gtest/gtest.h>

#include "gyroflip/io/calibration_file.hpp"

namespace {

using namespace gyroflip;

const std::string sha(64, 'a');

io::calibration_record two_runs() {
  io::calibration_record rec;
  rec.pooled.delta_n_dps = 0.0031;
  rec.pooled.stderr_correlated_dps = 1e-4;
  method::calibration c;
  c.delta_n_dps = 0.003;
  c.stderr_correlated_dps = 2e-4;
  c.temp_c = 20.0;
  c.cycles = 100;
  rec.files.push_back({"sim.csv", c, io::run_source{sha, 1234, "simulated", "gyroflip simulate"}});
  rec.files.push_back({"old.csv", c, std::nullopt});
  return rec;
}

TEST(CalibrationFile, EachRunsSourceIsWrittenAndReadBack) {
  const auto text = io::to_json(two_runs());
  ASSERT_TRUE(text) << text.err().message;
  EXPECT_NE(text->find("\"schema\":\"gyroflip.calibration/3\""), std::string::npos) << *text;
  const auto back = io::parse_calibration(*text, "cal.json");
  ASSERT_TRUE(back) << back.err().message;
  ASSERT_EQ(back->files.size(), 2u);
  ASSERT_TRUE(back->files[0].source.has_value());
  EXPECT_EQ(back->files[0].source->sha256, sha);
  EXPECT_EQ(back->files[0].source->size_bytes, 1234u);
  EXPECT_TRUE(back->files[0].source->simulated());
  EXPECT_EQ(back->files[0].source->origin_detail, "gyroflip simulate");
  EXPECT_FALSE(back->files[1].source.has_value());  // as schema 1 wrote it: nothing recorded
}

TEST(CalibrationFile, AMalformedSourceIsRefusedByName) {
  const std::string head = R"({"delta_n_dps": 0.01, "files": [{"delta_n_dps": 0.01, )";
  const auto refused = [&](const std::string& run, const std::string& words) {
    const auto r = io::parse_calibration(head + run + "}]}", "cal.json");
    ASSERT_FALSE(r) << run;
    EXPECT_NE(r.err().message.find(words), std::string::npos) << r.err().message;
    EXPECT_NE(r.err().message.find("cal.json"), std::string::npos) << r.err().message;
  };
  const std::string rest = R"(, "size_bytes": 1, "origin": "rig", "origin_detail": "x")";
  refused(R"("sha256": "abc")" + rest, "64 lowercase hex digits");
  refused(R"("sha256": ")" + std::string(64, 'G') + "\"" + rest, "64 lowercase hex digits");
  refused(R"("sha256": ")" + sha + R"(", "size_bytes": 1, "origin": "moon", "origin_detail": "x")",
          "'origin' must be");
  refused(R"("sha256": ")" + sha + R"(", "size_bytes": -1, "origin": "rig", "origin_detail": "x")",
          "'size_bytes'");
  refused(R"("sha256": ")" + sha +
              R"(", "size_bytes": 18446744073709551615, "origin": "rig", )"
              R"("origin_detail": "x")",
          "up to 2^53");
  refused(R"("sha256": ")" + sha +
              R"(", "size_bytes": 1, "origin": "rig", "origin_detail": "a\u0007b")",
          "one line of plain text");
  refused(R"("sha256": ")" + sha +
              R"(", "size_bytes": 1, "origin": "rig", "origin_detail": "a\u202eb")",
          "plain text");  // a bidi override would reorder the page around it
  for (const char* mark : {R"(\u200f)", R"(\u061c)", R"(\u2028)", R"(\ufeff)", R"(\u2066)"})
    refused(R"("sha256": ")" + sha + R"(", "size_bytes": 1, "origin": "rig", "origin_detail": "a)" +
                mark + R"(b")",
            "plain text");  // marks, a line separator, a BOM, an isolate (review N6)
  // All four or none (review D3: deleting the hash removed the "simulated" banner), and the run
  // is named.
  refused(R"("sha256": ")" + sha + R"(", "size_bytes": 1, "origin": "rig")",
          "files[0]: a run's source needs all");
  refused(R"("size_bytes": 1, "origin": "simulated", "origin_detail": "x")", "needs all");
}

TEST(CalibrationFile, AnotherSchemaOrFilesNotAnArrayIsRefused) {
  for (const char* text : {R"({"schema": "gyroflip.calibration/99", "delta_n_dps": 0.01})",
                           R"({"schema": "gyroflip.report/3", "delta_n_dps": 0.01})",
                           R"({"delta_n_dps": 0.01, "files": {}})"}) {
    const auto r = io::parse_calibration(text, "cal.json");
    EXPECT_FALSE(r) << text;
  }
  for (const char* text :
       {R"({"schema": "gyroflip.calibration/1", "delta_n_dps": 0.01})", R"({"delta_n_dps": 0.01})"})
    EXPECT_TRUE(io::parse_calibration(text, "cal.json")) << text;
}

}  // namespace
