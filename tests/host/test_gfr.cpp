// The .gfr recording format (issue 9, docs/FORMATS.md "Rig recording"): what the writer appends
// reads back; a cut anywhere in the last record is a torn tail that is skipped with a warning;
// any other damage is an error naming the record, never a silently different record.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "host/recorder/gfr.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace gfr = gyroflip::host::gfr;
using bytes = std::vector<std::uint8_t>;

bytes file_bytes(const std::string& path) {
  const std::string t = gyroflip::test::read_text(path);
  return bytes(t.begin(), t.end());
}

// A small file: META and three records of different kinds and sizes.
bytes sample(const std::string& path) {
  auto w = gfr::writer::create(path);
  EXPECT_TRUE(w);
  const std::string meta = R"({"scale_factor_v_per_dps":0.02})";
  EXPECT_TRUE(w->append(gfr::kind::meta, 5, bytes(meta.begin(), meta.end())));
  EXPECT_TRUE(w->append(gfr::kind::start, 6, {}));
  EXPECT_TRUE(w->append(gfr::kind::frame, 7, bytes{0x10, 1, 0, 9, 8, 7}));
  EXPECT_TRUE(w->append(gfr::kind::gap, 8, bytes{2, 3, 0, 0, 0}));
  EXPECT_TRUE(w->close());
  return file_bytes(path);
}

TEST(Gfr, WhatIsAppendedReadsBack) {
  gyroflip::test::temp_dir dir;
  const std::string path = dir.path() + "/a.gfr";
  sample(path);
  auto f = gfr::read(path);
  ASSERT_TRUE(f) << f.err().message;
  ASSERT_EQ(f->records.size(), 4u);
  EXPECT_TRUE(f->warnings.empty());
  EXPECT_EQ(f->records[1].type, gfr::kind::start);
  EXPECT_EQ(f->records[2].host_time_us, 7u);
  EXPECT_EQ(f->records[2].body, (bytes{0x10, 1, 0, 9, 8, 7}));
  EXPECT_EQ(f->records[3].type, gfr::kind::gap);
}

TEST(Gfr, ARecordingIsNeverOverwritten) {
  gyroflip::test::temp_dir dir;
  const std::string path = dir.path() + "/a.gfr";
  sample(path);
  auto w = gfr::writer::create(path);
  ASSERT_FALSE(w);
  EXPECT_NE(w.err().message.find("never overwritten"), std::string::npos);
}

TEST(Gfr, EveryCutInTheLastRecordIsATornTailSkippedWithAWarning) {
  gyroflip::test::temp_dir dir;
  const bytes whole = sample(dir.path() + "/a.gfr");
  const std::size_t last = gfr::record_overhead + 5;  // the GAP record
  for (std::size_t cut = 1; cut < last; ++cut) {
    SCOPED_TRACE(cut);
    const bytes b(whole.begin(), whole.end() - static_cast<std::ptrdiff_t>(cut));
    auto f = gfr::parse(b, "a.gfr");
    ASSERT_TRUE(f) << f.err().message;
    EXPECT_EQ(f->records.size(), 3u);
    ASSERT_EQ(f->warnings.size(), 1u);
    EXPECT_NE(f->warnings[0].find("a.gfr: record 4: "), std::string::npos) << f->warnings[0];
  }
}

// Every single-bit flip anywhere: an error naming the record, or (in the last record) a torn
// tail - never a file that reads as if whole but with another record.
TEST(Gfr, EveryBitFlipIsFoundAndNamed) {
  gyroflip::test::temp_dir dir;
  const bytes whole = sample(dir.path() + "/a.gfr");
  const auto original = gfr::parse(whole, "a.gfr");
  ASSERT_TRUE(original);
  const std::size_t last_start = whole.size() - (gfr::record_overhead + 5);
  for (std::size_t i = 0; i < whole.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      bytes b = whole;
      b[i] = static_cast<std::uint8_t>(b[i] ^ (1u << bit));
      auto f = gfr::parse(b, "a.gfr");
      SCOPED_TRACE(i * 8 + static_cast<std::size_t>(bit));
      if (f) {
        ASSERT_GE(i, last_start) << "a flip before the last record read as valid";
        EXPECT_EQ(f->records.size(), 3u);
        EXPECT_EQ(f->warnings.size(), 1u);
        continue;
      }
      const auto& m = f.err().message;
      EXPECT_EQ(m.rfind("a.gfr: record ", 0), 0u) << m;
      if (i < gfr::file_header_bytes) {
        EXPECT_EQ(m.rfind("a.gfr: record 0: ", 0), 0u) << m;
      }
    }
}

TEST(Gfr, HeaderProblemsSayWhatIsWrong) {
  gyroflip::test::temp_dir dir;
  const bytes whole = sample(dir.path() + "/a.gfr");
  const auto message = [](const bytes& b) {
    auto f = gfr::parse(b, "x.gfr");
    return f ? std::string("ok") : f.err().message;
  };
  EXPECT_NE(message(bytes(whole.begin(), whole.begin() + 10))
                .find("record 0: the file header is "
                      "cut short"),
            std::string::npos);
  bytes magic = whole;
  magic[1] = 'X';
  EXPECT_NE(message(magic).find("record 0: not a gyroflip rig recording"), std::string::npos);
  EXPECT_NE(message({}).find("record 0: not a gyroflip rig recording"), std::string::npos);
  // A newer version with a correct header checksum.
  bytes future = whole;
  future[8] = 2;
  const std::uint32_t crc = gfr::crc32(std::span<const std::uint8_t>(future.data(), 12));
  for (std::size_t k = 0; k < 4; ++k) future[12 + k] = static_cast<std::uint8_t>(crc >> (8 * k));
  EXPECT_NE(message(future).find("record 0: format version 2 is newer"), std::string::npos)
      << message(future);
  // Only the header: no META.
  EXPECT_NE(message(bytes(whole.begin(), whole.begin() + 16)).find("record 1: no META"),
            std::string::npos);
}

TEST(Gfr, Crc32IsTheStandardOne) {
  // CRC-32/ISO-HDLC check value of "123456789" (the CRC catalogue's check).
  const std::string s = "123456789";
  EXPECT_EQ(gfr::crc32(std::span<const std::uint8_t>(
                reinterpret_cast<const std::uint8_t*>(s.data()), s.size())),
            0xCBF43926u);
}

}  // namespace
