// The recording writer against the reader (issue 13 item 19): writing then reading a recording
// is the identity, bit for bit, for awkward doubles, empty angles and metadata.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/io/recording.hpp"
#include "gyroflip/io/recording_writer.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::io {
namespace {

TEST(RecordingWriter, RoundTrip) {
  const std::vector<double> awkward{1.0 / 3.0,           0.1,     -0.0,     1e-300, 5e-324,
                                    123456789.123456789, -2.5e-7, 9.999e99, 1e100,  -1e100,
                                    0.30000000000000004};
  std::vector<method::row> rows;
  for (std::size_t k = 0; k < 40; ++k) {
    const double a = awkward[k % awkward.size()];
    rows.push_back({0.001 * static_cast<double>(k) + (k == 7 ? 1e-9 : 0.0),
                    k % 5 == 4 ? table_moving : (k / 5 % 2 == 0 ? 0 : 1), a,
                    -273.15 + 1e-3 * static_cast<double>(k),
                    static_cast<std::uint32_t>(k % 3 == 0 ? 4294967295u : k + 1)});
  }
  const std::vector<csv_metadata> meta{{"sensor", "hz1-90-100a"},
                                       {"seed", "7"},
                                       {"path", "a\nb.toml"},  // a newline must not break the file
                                       {"name", "données"}};
  std::string text;
  append_recording_header(text, meta);
  const auto table = position_table::pair_0_180();
  for (const auto& r : rows) append_recording_row(text, r, table);
  test::temp_dir d;
  test::write_text(d.file("r.csv"), text);
  auto reader = recording_reader::open(d.file("r.csv"));
  ASSERT_TRUE(reader) << reader.err().message;
  ASSERT_EQ(reader->metadata().size(), meta.size());
  EXPECT_EQ(reader->metadata()[2].value, "a\\x0ab.toml");
  EXPECT_EQ(reader->metadata()[3].value, "données");
  method::row got;
  for (const auto& want : rows) {
    ASSERT_EQ(reader->next(got), csv_reader::step::row) << reader->last_error().message;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(got.time_s), std::bit_cast<std::uint64_t>(want.time_s));
    EXPECT_EQ(got.position, want.position);  // the table read from the angles: 0 and 180
    EXPECT_EQ(std::bit_cast<std::uint64_t>(got.rate_dps),
              std::bit_cast<std::uint64_t>(want.rate_dps))
        << want.rate_dps;
    EXPECT_EQ(std::bit_cast<std::uint64_t>(got.temp_c), std::bit_cast<std::uint64_t>(want.temp_c));
    EXPECT_EQ(got.n_avg, want.n_avg);
  }
  EXPECT_EQ(reader->next(got), csv_reader::step::end);
  EXPECT_TRUE(reader->warnings().empty());
}

}  // namespace
}  // namespace gyroflip::io
