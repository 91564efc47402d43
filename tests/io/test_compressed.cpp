// Compressed input (issue 34 item 4): .gz, .xz and .zst read as they are decompressed, by every
// series reader (CSV, .npy, raw), identical to the plain file; damaged or cut files are errors
// naming the file; a missing column gets a suggestion.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "gyroflip/io/compressed.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/io/series.hpp"
#include "support/ros_bags.hpp"
#include "support/temp_dir.hpp"

namespace gyroflip::test {
namespace {

constexpr std::size_t rows = 15000;  // 650 kB of text: three of the reader's 256 KB blocks

// A CSV with a time column and two columns of known values (written with 17 digits).
std::string csv_text() {
  std::string s = "# sensor: test\ntime_s,gyro_x_dps,gyro_y_dps\n";
  for (std::size_t k = 0; k < rows; ++k) {
    const double t = static_cast<double>(k) * 0.01;
    s += fmt::format("{:.2f},{:.17g},{:.17g}\n", t, std::sin(0.001 * static_cast<double>(k)),
                     1e-3 * static_cast<double>(k % 97));
  }
  return s;
}

std::vector<std::vector<double>> read_two(const std::string& path) {
  io::series_options o;
  auto s = io::read_series_columns(path, o, {"gyro_x_dps", "gyro_y_dps"});
  EXPECT_TRUE(s) << (s ? "" : s.err().message);
  if (!s) return {};
  EXPECT_NEAR((*s)[0].tau0_s(), 0.01, 1e-12);
  std::vector<std::vector<double>> out;
  for (const auto& one : *s) out.emplace_back(one.values().begin(), one.values().end());
  return out;
}

TEST(Compressed, EachFormatReadsAsThePlainFile) {
  temp_dir d;
  const std::string text = csv_text();
  std::ofstream(d.file("a.csv"), std::ios::binary) << text;
  const auto plain = read_two(d.file("a.csv"));
  ASSERT_EQ(plain.size(), 2U);
  ASSERT_EQ(plain[0].size(), rows);
  // The truth, not only the plain reader: row 1234's values.
  EXPECT_EQ(plain[0][1234], std::sin(1.234));
  for (const char* ext : {".gz", ".xz", ".zst"}) {
    const std::string path = d.file(std::string("a.csv") + ext);
    write_compressed(path, text);
    EXPECT_LT(read_bytes(path).size(), text.size() / 2) << ext;  // it is compressed
    EXPECT_EQ(read_two(path), plain) << ext;
  }
}

TEST(Compressed, ConcatenatedMembersAndFramesAreReadOneAfterAnother) {
  temp_dir d;
  const std::string text = csv_text();
  const std::string first = text.substr(0, text.size() / 3), rest = text.substr(text.size() / 3);
  std::ofstream(d.file("a.csv"), std::ios::binary) << text;
  const auto plain = read_two(d.file("a.csv"));
  for (const char* ext : {".gz", ".xz", ".zst"}) {
    write_compressed(d.file(std::string("p1") + ext), first);
    write_compressed(d.file(std::string("p2") + ext), rest);
    const std::string path = d.file(std::string("cat.csv") + ext);
    std::ofstream(path, std::ios::binary) << read_bytes(d.file(std::string("p1") + ext))
                                          << read_bytes(d.file(std::string("p2") + ext));
    EXPECT_EQ(read_two(path), plain) << ext;
  }
}

TEST(Compressed, ACutOrDamagedFileIsAnErrorNamingIt) {
  temp_dir d;
  const std::string text = csv_text();
  for (const char* ext : {".gz", ".xz", ".zst"}) {
    const std::string whole = d.file(std::string("w.csv") + ext);
    write_compressed(whole, text);
    const std::string bytes = read_bytes(whole);
    // Cut at a line's end of the decompressed text would still look whole: cut the compressed
    // stream in its middle and just before its end (the trailer with its check).
    for (const std::size_t keep : {bytes.size() / 2, bytes.size() - 3}) {
      const std::string cut = d.file(fmt::format("cut{}.csv{}", keep, ext));
      std::ofstream(cut, std::ios::binary) << bytes.substr(0, keep);
      io::series_options o;
      o.column = "gyro_x_dps";
      auto s = io::read_series(cut, o);
      ASSERT_FALSE(s) << ext << " kept " << keep;
      EXPECT_NE(s.err().message.find(cut), std::string::npos) << s.err().message;
      EXPECT_NE(s.err().message.find("compressed byte"), std::string::npos) << s.err().message;
    }
    // One byte changed in the middle: the format's check (CRC-32, CRC-64, XXH64) or the data.
    std::string bad = bytes;
    bad[bad.size() / 2] = static_cast<char>(bad[bad.size() / 2] ^ 0x5a);
    const std::string damaged = d.file(std::string("bad.csv") + ext);
    std::ofstream(damaged, std::ios::binary) << bad;
    io::series_options o;
    o.column = "gyro_x_dps";
    auto s = io::read_series(damaged, o);
    ASSERT_FALSE(s) << ext;
    EXPECT_NE(s.err().message.find(damaged), std::string::npos) << s.err().message;
  }
}

TEST(Compressed, ANameThatLiesAboutTheCompressionIsAnError) {
  temp_dir d;
  std::ofstream(d.file("plain.csv.gz")) << "time_s,x\n0,1\n";
  io::series_options o;
  o.column = "x";
  auto s = io::read_series(d.file("plain.csv.gz"), o);
  ASSERT_FALSE(s);
  EXPECT_NE(s.err().message.find("not gzip data"), std::string::npos) << s.err().message;
  std::ofstream(d.file("empty.csv.zst")) << "";
  s = io::read_series(d.file("empty.csv.zst"), o);
  ASSERT_FALSE(s);
  EXPECT_NE(s.err().message.find("empty file"), std::string::npos) << s.err().message;
}

TEST(Compressed, NpyAndRawFilesToo) {
  temp_dir d;
  std::vector<double> v(5000);
  for (std::size_t k = 0; k < v.size(); ++k) v[k] = std::cos(0.01 * static_cast<double>(k));
  const std::string raw(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (5000,), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string npy = "\x93NUMPY\x01";
  npy += '\0';
  npy += static_cast<char>(header.size() & 0xFF);
  npy += static_cast<char>(header.size() >> 8);
  npy += header + raw;
  write_compressed(d.file("a.npy.xz"), npy);
  write_compressed(d.file("a.f64.zst"), raw);
  write_compressed(d.file("a.bin.gz"), raw);
  io::series_options o;
  o.sample_rate_hz = 200.0;
  for (const char* name : {"a.npy.xz", "a.f64.zst", "a.bin.gz"}) {
    auto s = io::read_series(d.file(name), o);
    ASSERT_TRUE(s) << name << ": " << s.err().message;
    EXPECT_EQ(std::vector<double>(s->values().begin(), s->values().end()), v) << name;
    EXPECT_DOUBLE_EQ(s->tau0_s(), 0.005);
  }
  // A raw file whose decompressed length is no whole number of samples.
  write_compressed(d.file("odd.f64.gz"), raw.substr(0, raw.size() - 3));
  auto s = io::read_series(d.file("odd.f64.gz"), o);
  ASSERT_FALSE(s);
  EXPECT_NE(s.err().message.find("not a whole number"), std::string::npos) << s.err().message;
}

TEST(Compressed, NamesAndTheirFormat) {
  EXPECT_EQ(io::compression_of("a.csv.gz"), io::compression::gzip);
  EXPECT_EQ(io::compression_of("a.csv.xz"), io::compression::xz);
  EXPECT_EQ(io::compression_of("a.bag.zst"), io::compression::zstd);
  EXPECT_EQ(io::compression_of("a.csv"), io::compression::none);
  EXPECT_EQ(io::without_compression("dir.gz/a.npy.zst"), "dir.gz/a.npy");
}

TEST(MissingColumn, TheNearestNameIsSuggested) {
  temp_dir d;
  std::ofstream(d.file("a.csv"))
      << "time_s,gyro_x_dps,gyro_y_dps,temp_c\n0,1,2,3\n0.1,1,2,3\n0.2,1,2,3\n";
  io::series_options o;
  for (const auto& [asked, meant] :
       std::vector<std::pair<std::string, std::string>>{{"gyro_x", "gyro_x_dps"},
                                                        {"Gyro_Y_dps", "gyro_y_dps"},
                                                        {"temp", "temp_c"},
                                                        {"gyro_x_dsp", "gyro_x_dps"}}) {
    o.column = asked;
    auto s = io::read_series(d.file("a.csv"), o);
    ASSERT_FALSE(s);
    EXPECT_NE(s.err().message.find(fmt::format("did you mean '{}'?", meant)), std::string::npos)
        << s.err().message;
    EXPECT_NE(s.err().message.find("time_s,gyro_x_dps,gyro_y_dps,temp_c"), std::string::npos)
        << s.err().message;
  }
  o.column = "pressure_pa";  // nothing near: no guess
  auto s = io::read_series(d.file("a.csv"), o);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.err().message.find("did you mean"), std::string::npos) << s.err().message;
  EXPECT_EQ(io::did_you_mean("rate", {"rate_dps", "rate_dph"}), "rate_dps");
}

}  // namespace
}  // namespace gyroflip::test
