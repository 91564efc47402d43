// The calibration file's runs and where they came from (schema gyroflip.calibration/2,
// docs/FORMATS.md): written and read back, refused when malformed, and absent in schema 1 files.
#include <fstream>
#include <sstream>
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
  EXPECT_NE(text->find("\"schema\":\"gyroflip.calibration/5\""), std::string::npos) << *text;
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

// Issue 33 (d): dN is a set of named terms (schema 4). Every older file still reads, its terms
// the 0/180 schemes' one term `delta_n` = its pooled dN with its correlated error; the dN that
// compensate applies is the same as before. Files written by earlier versions (tests/vectors/
// calibration/PROVENANCE.md).
TEST(CalibrationFile, OlderSchemasReadAsTheOneTermDeltaN) {
  struct old_file {
    const char* name;
    double delta_n_dps;
    bool model;
  };
  for (const auto& f : {old_file{"schema1_single.json", 0.004776510345462761, false},
                        old_file{"schema2_runs_with_sources.json", 0.0, true},
                        old_file{"schema3_one_run_geometry.json", 0.3927323024999996, false},
                        old_file{"schema3_two_runs_model_simple.json", 0.0, true}}) {
    const std::string path = std::string(GYROFLIP_VECTORS_DIR) + "/calibration/" + f.name;
    const auto rec = io::read_calibration_file(path);
    ASSERT_TRUE(rec) << rec.err().message;
    SCOPED_TRACE(f.name);
    if (f.delta_n_dps != 0.0) {
      EXPECT_EQ(rec->pooled.delta_n_dps, f.delta_n_dps);
    }
    ASSERT_EQ(rec->terms.size(), 1u);
    EXPECT_EQ(rec->terms[0].name, "delta_n");
    EXPECT_EQ(rec->terms[0].value_dps, rec->pooled.delta_n_dps);
    EXPECT_EQ(rec->terms[0].stderr_correlated_dps, rec->pooled.stderr_correlated_dps);
    EXPECT_EQ(rec->model.has_value(), f.model);
    // Written again: schema 5 with the same term, and read back the same.
    const auto text = io::to_json(*rec);
    ASSERT_TRUE(text) << text.err().message;
    EXPECT_NE(text->find("\"schema\":\"gyroflip.calibration/5\""), std::string::npos);
    const auto back = io::parse_calibration(*text, "again.json");
    ASSERT_TRUE(back) << back.err().message;
    EXPECT_EQ(back->terms, rec->terms);
    EXPECT_EQ(io::delta_n_model_of(*back).eval(20.0), io::delta_n_model_of(*rec).eval(20.0));
  }
}

TEST(CalibrationFile, TermsAreWrittenAndAnEditedOrForeignTermIsRefused) {
  const auto text = io::to_json(two_runs());
  ASSERT_TRUE(text);
  EXPECT_NE(
      text->find(
          R"("terms":[{"name":"delta_n","stderr_correlated_dps":0.0001,"value_dps":0.0031}])"),
      std::string::npos)
      << *text;
  const auto with_terms = [](const std::string& terms) {
    return io::parse_calibration(
        R"({"schema": "gyroflip.calibration/4", "delta_n_dps": 0.01, "stderr_correlated_dps": 0.001, "terms": )" +
            terms + "}",
        "cal.json");
  };
  const auto good =
      with_terms(R"([{"name": "delta_n", "value_dps": 0.01, "stderr_correlated_dps": 0.001}])");
  ASSERT_TRUE(good) << good.err().message;
  EXPECT_EQ(good->terms.size(), 1u);
  const auto refused = [&](const std::string& terms, const std::string& words) {
    const auto r = with_terms(terms);
    ASSERT_FALSE(r) << terms;
    EXPECT_NE(r.err().message.find(words), std::string::npos) << r.err().message;
    EXPECT_NE(r.err().message.find("cal.json"), std::string::npos) << r.err().message;
  };
  refused(R"([{"name": "delta_n", "value_dps": 0.02}])", "one of them was edited");
  refused(R"([{"name": "h2_cos", "value_dps": 0.01}])", "not a term of the pairing 'abba'");
  refused(R"([])", "lacks the term 'delta_n'");
  refused(R"([{"name": "delta_n", "value_dps": 0.01}, {"name": "delta_n", "value_dps": 0.01}])",
          "given twice");
  refused(R"({"delta_n": 0.01})", "'terms' must be an array");
  refused(R"([{"name": "delta_n", "value_dps": 1e300}])", "value_dps");
  refused(R"([{"name": "delta_n", "value_dps": 0.01, "stderr_correlated_dps": -1}])",
          "stderr_correlated_dps");
}

}  // namespace
