// Strict CSV reader: rules of docs/FORMATS.md, error positions, BOM/CRLF, atomic output.
#include <gtest/gtest.h>

#include <cmath>

#include "gyroflip/io/atomic_file.hpp"
#include "gyroflip/io/csv.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::io {
namespace {

using test::temp_dir;
using test::write_text;

TEST(Csv, ReadsColumnsByNameWithCommentsBomAndCrlf) {
  temp_dir d;
  const auto p = d.file("a.csv");
  write_text(p,
             "\xEF\xBB\xBF# sensor: hz1\r\n#free comment\r\nb, a ,c\r\n1,2,3\r\n\r\n# mid\r\n4, +5 "
             ",6\r\n");
  auto r = csv_reader::open(p);
  ASSERT_TRUE(r) << r.err().message;
  ASSERT_EQ(r->metadata().size(), 1u);
  EXPECT_EQ(r->metadata()[0].key, "sensor");
  EXPECT_EQ(r->metadata()[0].value, "hz1");
  const auto cols = read_numeric_columns(p, {"a", "c"});
  ASSERT_TRUE(cols) << cols.err().message;
  EXPECT_EQ(cols.value()[0], (std::vector<double>{2.0, 5.0}));
  EXPECT_EQ(cols.value()[1], (std::vector<double>{3.0, 6.0}));
}

struct bad_case {
  const char* text;
  const char* where;  // expected "FILE-basename:LINE..." fragment after the file name
  const char* what;   // expected fragment of the message
};

TEST(Csv, BadInputNamesFileLineAndColumn) {
  const bad_case cases[] = {
      {"", ": empty file", "empty"},
      {"# only comments\n\n", ":2: no header", "no header"},
      {"a,b\n1,2\n3\n", ":3:2: row has 1 field", "header has 2"},
      {"a,b\n1,2\n3,4,5\n", ":3:6: row has 3 fields", "header has 2"},
      {"a,b\n1,x\n", ":2:3: 'x' is not a number", "column 'b'"},
      {"a,b\n1,nan\n", ":2:3: 'nan' is not a finite number", "column 'b'"},
      {"a,b\n1,-inf\n", ":2:3: '-inf' is not a finite number", "column 'b'"},
      {"a,b\n1,\n", ":2:3: empty field", "column 'b'"},
      {"a,b\n1,1e999\n", ":2:3: '1e999' is out of the range", "column 'b'"},
      {"a,a\n1,2\n", ":1:3: duplicated column 'a'", "fields 1 and 2"},
      {"x,y\n1,2\n", ":1:1: missing required column 'a'", "header: x,y"},
  };
  temp_dir d;
  for (const auto& c : cases) {
    const auto p = d.file("bad.csv");
    write_text(p, c.text);
    const auto r = read_numeric_columns(p, {"a", "b"});
    ASSERT_FALSE(r) << c.text;
    EXPECT_EQ(r.err().code, errc::bad_input);
    EXPECT_NE(r.err().message.find(std::string("bad.csv") + c.where), std::string::npos)
        << r.err().message;
    EXPECT_NE(r.err().message.find(c.what), std::string::npos) << r.err().message;
  }
}

TEST(Csv, BinaryHugeLineMissingAndDirectory) {
  temp_dir d;
  std::string junk;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 256; ++i) junk.push_back(static_cast<char>(i));
  write_text(d.file("junk.bin"), junk);
  auto r = csv_reader::open(d.file("junk.bin"));
  ASSERT_FALSE(r);
  EXPECT_NE(r.err().message.find("binary"), std::string::npos);

  write_text(d.file("huge.csv"), "a,b\n" + std::string(std::size_t{2} << 20, '1'));
  const auto h = read_numeric_columns(d.file("huge.csv"), {"a"});
  ASSERT_FALSE(h);
  EXPECT_NE(h.err().message.find("huge.csv:2"), std::string::npos) << h.err().message;

  const auto m = csv_reader::open(d.file("missing.csv"));
  ASSERT_FALSE(m);
  EXPECT_EQ(m.err().code, errc::io);
  const auto dir = csv_reader::open(d.path());
  ASSERT_FALSE(dir);
  EXPECT_NE(dir.err().message.find("directory"), std::string::npos);
}

TEST(AtomicFile, NothingAppearsUntilCommit) {
  temp_dir d;
  const auto p = d.file("out.csv");
  {
    auto f = atomic_file::create(p);
    ASSERT_TRUE(f);
    f->write("partial");
  }  // destroyed without commit: an error path
  EXPECT_FALSE(test::exists(p));
  auto f = atomic_file::create(p);
  ASSERT_TRUE(f);
  f->write("done\n");
  ASSERT_TRUE(f->commit());
  EXPECT_EQ(test::read_text(p), "done\n");
  EXPECT_FALSE(atomic_file::create(d.file("no-such-dir/x.csv")));
}

}  // namespace
}  // namespace gyroflip::io

#include "gyroflip/io/recording.hpp"
#include "gyroflip/workflow/recordings.hpp"

namespace gyroflip::io {
namespace {

// Regression (2026-11-22): without temp_c and n_avg the absent columns' placeholder slots
// stole time_s's slot and every row failed with a garbage column number.
TEST(Recording, MinimalThreeColumnsAnyOrderExtraColumnsIgnored) {
  test::temp_dir d;
  std::string text = "rate_dps,note,angle_deg,time_s\n";
  for (int k = 0; k < 10; ++k)
    text += std::to_string(k % 2 == 0 ? 0.5 : -0.3) + ",x," + (k % 2 == 0 ? "0" : "180") + "," +
            std::to_string(k) + "\n";
  test::write_text(d.file("min.csv"), text);
  const auto rc = workflow::read_cycles(d.file("min.csv"), method::pairing::simple);
  ASSERT_TRUE(rc) << rc.err().message;
  EXPECT_FALSE(rc->has_temp);
  ASSERT_EQ(rc->cycles.size(), 5u);
  EXPECT_DOUBLE_EQ(rc->cycles[0].rate_dps, 0.4);
  EXPECT_DOUBLE_EQ(rc->cycles[0].bias_dps, 0.1);
  EXPECT_TRUE(std::isnan(rc->cycles[0].temp_c));
  EXPECT_DOUBLE_EQ(rc->cycles[4].time_s, 8.5);
}

}  // namespace
}  // namespace gyroflip::io

#include <charconv>
#include <cstring>
#include <random>

namespace gyroflip::io {
namespace {

TEST(PlainDecimal, AgreesWithFromCharsBitForBit) {
  // The fast path must give the correctly rounded double that from_chars gives, for every
  // plain decimal it accepts; 200k random ones with 1-19 characters and random point positions.
  std::mt19937_64 rng(42);
  std::size_t accepted = 0;
  for (int n = 0; n < 200000; ++n) {
    std::string s = (rng() % 2 == 0) ? "-" : "";
    const std::size_t digits = 1 + rng() % 18;
    const std::size_t point = rng() % (digits + 2);  // digits + 1: no point
    for (std::size_t d = 0; d < digits; ++d) {
      if (d == point) s += '.';
      s += static_cast<char>('0' + rng() % 10);
    }
    double fast = 0.0;
    if (!detail::parse_plain_decimal(s.data(), s.data() + s.size(), fast)) continue;
    ++accepted;
    double ref = 0.0;
    std::from_chars(s.data(), s.data() + s.size(), ref);
    ASSERT_EQ(std::memcmp(&fast, &ref, sizeof fast), 0) << s;
  }
  EXPECT_GT(accepted, 150000u);  // most short decimals take the fast path
}

// The one-pass row path (peek_plain) against the general one (next, parse) on the same file:
// random rows of plain decimals and of spellings only the general path reads (blanks, '+',
// exponents, CR, long mantissas, wrong field counts, empty fields). Where the fast path takes a
// row its values are bit for bit the general path's; whatever it declines, next() reads. Fails
// if the fast path accepts one row the general path reads differently or refuses.
TEST(PlainRow, TakesOnlyRowsTheGeneralPathReadsAlikeBitForBit) {
  std::mt19937_64 rng(33);
  const auto number = [&] {
    std::string s = rng() % 4 == 0 ? "-" : "";
    const std::size_t digits = rng() % 22;  // 0: an empty field, or "-"/"." alone
    const std::size_t point = rng() % (digits + 2);
    for (std::size_t d = 0; d < digits; ++d) {
      if (d == point) s += '.';
      s += static_cast<char>('0' + rng() % 10);
    }
    std::string out;  // with a spelling for the general path now and then
    const auto kind = rng() % 24;
    out += kind == 0 ? " " : kind == 2 ? "+" : "";
    out += kind == 4 ? std::string(".5") : s;
    out += kind == 1 ? "e3" : kind == 3 ? "." : "";
    return out;
  };
  std::string text = "a,b,c,d\n";
  const int rows = 20000;
  for (int k = 0; k < rows; ++k) {
    const int fields = rng() % 50 == 0 ? 3 : 4;
    for (int f = 0; f < fields; ++f) {
      if (f > 0) text += ',';
      text += number();
    }
    text += rng() % 30 == 0 ? "\r\n" : "\n";
  }
  temp_dir d;
  const auto p = d.file("rows.csv");
  write_text(p, text);
  auto fast = csv_reader::open(p);
  auto slow = csv_reader::open(p);
  ASSERT_TRUE(fast && slow);
  fast->select({0, 2, 3});  // column b unselected, as a recording's extra columns are
  slow->select({0, 2, 3});
  std::size_t taken = 0, compared = 0;
  while (true) {
    csv_reader::plain_row row;
    const bool plain = fast->peek_plain(row);
    const auto s = slow->next();
    if (!plain) {
      const auto f = fast->next();  // the general path on the declined row
      ASSERT_EQ(f, s);
      if (s == csv_reader::step::end) break;
      continue;
    }
    ++taken;
    ASSERT_EQ(s, csv_reader::step::row)
        << "the fast path took a row the general path refuses, line " << slow->line() << ": "
        << slow->last_error().message;
    fast->commit_plain(row);
    ASSERT_EQ(fast->line(), slow->line());
    for (std::size_t i = 0; i < 3; ++i) {
      ASSERT_EQ(row.empty[i], slow->cell(i).empty()) << "line " << slow->line();
      if (row.empty[i]) continue;
      double v = 0.0;
      ASSERT_TRUE(slow->parse(i, v))
          << "line " << slow->line() << ": " << slow->last_error().message;
      ASSERT_EQ(std::memcmp(&v, &row.value[i], sizeof v), 0)
          << "line " << slow->line() << " cell " << i << ": " << slow->cell(i);
      ++compared;
    }
  }
  EXPECT_GT(taken, static_cast<std::size_t>(rows) / 4);  // the common rows take the fast path
  EXPECT_GT(compared, 10000u);
}

TEST(PlainDecimal, RejectsWhatItCannotDoExactly) {
  for (const char* s : {"", "-", ".", "1e5", "nan", "inf", "+1", " 1", "1 ", "1.2.3", "0x10",
                        "12345678901234567890", "9007199254740993", "1.00000000000000000000001"}) {
    double v = 0.0;
    EXPECT_FALSE(detail::parse_plain_decimal(s, s + std::strlen(s), v)) << s;
  }
  double v = 0.0;
  const char* edge = "9007199254740992";  // 2^53: still exact
  ASSERT_TRUE(detail::parse_plain_decimal(edge, edge + 16, v));
  EXPECT_EQ(v, 9007199254740992.0);
}

}  // namespace
}  // namespace gyroflip::io
