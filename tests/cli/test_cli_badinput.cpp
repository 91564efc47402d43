// Inputs that were silently wrong or expensive before issue 13 (reviewed 2026-11-22): each case
// failed on that day's main. Every one must give exit 2, a message naming the file (and its
// line/column or record where one exists) and no output file.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
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

// A .npy file as numpy.save writes it (format 1.0): magic, version, header length, the dict
// padded with spaces to a multiple of 64 bytes, '\n', then the data. `dict` is the dict text.
std::string npy(const std::string& dict, std::size_t n_values, int header_len_delta = 0) {
  std::string h = dict;
  while ((10 + h.size() + 1) % 64 != 0) h += ' ';
  h += '\n';
  const auto len = static_cast<std::size_t>(static_cast<long>(h.size()) + header_len_delta);
  std::string out = "\x93NUMPY";
  out += '\x01';
  out += '\x00';
  out += static_cast<char>(len & 0xff);
  out += static_cast<char>(len >> 8);
  out += h;
  for (std::size_t i = 0; i < n_values; ++i) {
    const double v = 0.001 * static_cast<double>(i % 7);
    char b[8];
    std::memcpy(b, &v, 8);
    out.append(b, 8);
  }
  return out;
}

std::string dict_of(const std::string& shape, const std::string& descr = "'<f8'",
                    const std::string& fortran = "False") {
  return "{'descr': " + descr + ", 'fortran_order': " + fortran + ", 'shape': " + shape + ", }";
}

// Item 5: the header's shape was ignored (a truncated file analysed as fewer samples, a
// header-length field off by 8 read header bytes as a sample, shapes (0,), (-1,), (),
// (10**12,) accepted); 0 or 1 samples failed with exit 1 and no file name. (Float32 and 2-D
// tables are read since issue 12; a table needs its column.)
TEST(CliBadInput, NpyHeaderAndLengthAreCheckedExactly) {
  temp_dir d;
  struct npy_case {
    std::string name;
    std::string bytes;
    std::string says;
  };
  const std::vector<npy_case> cases{
      {"truncated", npy(dict_of("(100,)"), 99), "announces 100 samples"},
      {"padded", npy(dict_of("(100,)"), 101), "announces 100 samples"},
      {"len_plus_8", npy(dict_of("(100,)"), 100, 8), "newline"},
      {"len_minus_8", npy(dict_of("(100,)"), 100, -8), "newline"},
      {"shape_0", npy(dict_of("(0,)"), 0), "too few"},
      {"shape_1", npy(dict_of("(1,)"), 1), "too few"},
      {"shape_neg", npy(dict_of("(-1,)"), 4), "shape (-1,)"},
      {"shape_scalar", npy(dict_of("()"), 1), "1-D"},
      {"shape_huge", npy(dict_of("(1000000000000,)"), 4), "announces 1000000000000"},
      // Issue 21: sizes past 2^64 bytes wrapped, "announces 2305843009213693952 samples (0
      // bytes) but the file holds 0 data bytes".
      {"shape_2p61", npy(dict_of("(2305843009213693952,)"), 0),
       "announces 2305843009213693952 samples (more than 2^64 bytes) but the file holds 0 data "
       "bytes"},
      {"shape_2p62_x_4", npy(dict_of("(4611686018427387904, 4)"), 4),
       "announces 4611686018427387904 x 4 values (more than 2^64 bytes) but the file holds 32"},
      {"shape_3d", npy(dict_of("(3, 2, 1)"), 6), "1-D (N,) or 2-D (N, M)"},
      {"table_without_column", npy(dict_of("(3, 2)"), 6), "has 2 columns: give a column number"},
      {"f2", npy(dict_of("(8,)", "'<f2'"), 2), "'<f8' or float32 '<f4'"},
      {"big_endian", npy(dict_of("(8,)", "'>f8'"), 8), "'<f8'"},
      {"no_shape", npy("{'descr': '<f8', 'fortran_order': False, }", 8), "once each"},
      {"version",
       [] {
         std::string b = npy(dict_of("(8,)"), 8);
         b[6] = '\x07';
         return b;
       }(),
       "version 7.0"},
  };
  for (const auto& c : cases) {
    const std::string path = d.file(c.name + ".npy");
    write_text(path, c.bytes);
    const auto r = run_cli({"adev", path, "--rate", "100", "-o", d.file("out.csv")});
    EXPECT_EQ(r.exit_code, 2) << c.name << ": " << r.err;
    EXPECT_EQ(r.err.rfind("gyroflip: error: " + path + ": ", 0), 0u) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.name << ": " << r.err;
    EXPECT_FALSE(exists(d.file("out.csv"))) << c.name;
  }
  // The same array in Fortran order (identical for 1-D) and a good file are read.
  write_text(d.file("good.npy"), npy(dict_of("(100,)"), 100));
  write_text(d.file("fortran.npy"), npy(dict_of("(100,)", "'<f8'", "True"), 100));
  const auto good = run_cli({"adev", d.file("good.npy"), "--rate", "100"});
  EXPECT_EQ(good.exit_code, 0) << good.err;
  EXPECT_EQ(run_cli({"adev", d.file("fortran.npy"), "--rate", "100"}).out, good.out);
  // Raw float64 too: one sample is too few.
  write_text(d.file("one.f64"), std::string(8, '\0'));
  const auto raw = run_cli({"adev", d.file("one.f64"), "--rate", "100"});
  EXPECT_EQ(raw.exit_code, 2);
  EXPECT_NE(raw.err.find(d.file("one.f64") + ": 1 sample: too few"), std::string::npos) << raw.err;
}

// Item 6: `simulate --sensor DIR` or an empty .toml simulated a noise-free default sensor, exit 0.
TEST(CliBadInput, PresetFileMustNameItselfAndEveryFigure) {
  temp_dir d;
  write_text(d.file("empty.toml"), "");
  write_text(d.file("noname.toml"), "base = \"hz1-90-100a\"\n");
  write_text(d.file("partial.toml"), "name = \"x\"\narw_dps_rthz = 0.01\n");
  const std::vector<std::pair<std::string, std::string>> cases{
      {d.path(), "not a regular file"},
      {d.file("empty.toml"), "needs name"},
      {d.file("noname.toml"), "needs name"},
      {d.file("partial.toml"), "every parameter must be given; missing: range_dps"},
      {d.file("absent.toml"), "cannot open"},
  };
  for (const auto& [file, says] : cases) {
    const auto r =
        run_cli({"simulate", "--sensor", file, "--duration", "10", "-o", d.file("o.csv")});
    EXPECT_EQ(r.exit_code, 2) << file;
    EXPECT_EQ(r.err.rfind("gyroflip: error: " + file + ": ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_FALSE(exists(d.file("o.csv")));
  }
  write_text(d.file("ok.toml"), "name = \"x\"\nbase = \"hz1-90-100a\"\n");
  EXPECT_EQ(run_cli({"simulate", "--sensor", d.file("ok.toml"), "--duration", "10"}).exit_code, 0);
}

// A stationary recording from the simulator (a few minutes), written to `path`.
void simulated_recording(const std::string& path, int duration_s = 300) {
  const auto r = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration",
                          std::to_string(duration_s), "-o", path});
  ASSERT_EQ(r.exit_code, 0) << r.err;
}

// Item 7: a calibration file with 1e400 ended in "internal error [json.exception...]", exit 1;
// item 13: JSON errors carry FILE:LINE:COL and no raw control bytes.
TEST(CliBadInput, CalibrationJsonErrorsNameFileLineAndColumn) {
  temp_dir d;
  simulated_recording(d.file("r.csv"));
  const std::vector<std::pair<std::string, std::string>> cases{
      {R"({"delta_n_dps": 1e400})", "c.json:1:21: not valid JSON: number overflow"},
      {"{\n  \"delta_n_dps\": 0.1,\n  x }", "c.json:3:3: not valid JSON"},
      {"[1, 2", "c.json:1:5: not valid JSON"},
      {"\x01\x02", "c.json:1:1: not valid JSON: '<U+0001>'"},
      {R"({"delta_n_dps": "a"})", "c.json: malformed calibration: type must be number"},
  };
  for (const auto& [text, says] : cases) {
    write_text(d.file("c.json"), text);
    const auto r = run_cli({"compensate", d.file("r.csv"), "--calibration", d.file("c.json")});
    EXPECT_EQ(r.exit_code, 2) << text;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    for (char c : r.err) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7f)) << r.err;
  }
}

// Item 7: a recording named with invalid UTF-8 (`bad\xff.csv`) made --json throw
// ("internal error", exit 1). JSON cannot carry the name: exit 2 naming the file (escaped);
// text output works.
TEST(CliBadInput, FileNameThatIsNotUtf8) {
  temp_dir d;
  const std::string bad = d.file("bad\xff.csv");
  simulated_recording(bad);
  for (const auto& cmd :
       std::vector<std::vector<std::string>>{{"compensate", bad, "--delta-n", "0", "--json"},
                                             {"calibrate", bad},
                                             {"adev", bad, "--json"},
                                             {"noise", bad, "--json"}}) {
    const auto r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd[0] << ": " << r.err;
    EXPECT_NE(r.err.find(d.file("bad\\xff.csv") + ": the file name is not valid UTF-8"),
              std::string::npos)
        << r.err;
  }
  EXPECT_EQ(run_cli({"adev", bad}).exit_code, 0);
  EXPECT_EQ(run_cli({"compensate", bad, "--delta-n", "0"}).exit_code, 0);
}

// Item 13: CLI11's own usage errors ("file is required\nRun with --help ...") did not follow the
// documented `gyroflip: error: ...` form; messages echoed whole headers and raw control bytes.
TEST(CliBadInput, MessagesFollowOneFormAndStayShortAndPrintable) {
  for (const auto& args :
       std::vector<std::vector<std::string>>{{"adev"},
                                             {"adev", "x.csv", "--bogus"},
                                             {"simulate", "--sensor", "x", "--duration", "abc"},
                                             {},
                                             {"adev", "x.csv", "--kind", "foo"},
                                             {"adev", "x.csv", "--ci", "1"}}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err.rfind("gyroflip: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  temp_dir d;
  // A 512 KiB header without the column, and a header with control bytes.
  write_text(d.file("wide.csv"), std::string(512 * 1024, 'h') + "\n1\n2\n3\n");
  write_text(d.file("ctrl.csv"), "time_s,\x1b[31mred\n1,2\n2,3\n3,4\n");
  for (const auto& f : {d.file("wide.csv"), d.file("ctrl.csv")}) {
    const auto r = run_cli({"adev", f});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find(f + ":1:1: missing required column 'rate_dps'"), std::string::npos)
        << r.err.substr(0, 300);
    EXPECT_LT(r.err.size(), 600u);
    for (char c : r.err) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7f)) << r.err;
  }
}

// Item 10: a CSV cut inside its last field (`...,20.03,2` where n_avg was 256) was read as valid.
TEST(CliBadInput, RecordingCutInsideItsLastRow) {
  temp_dir d;
  simulated_recording(d.file("whole.csv"));
  std::string text = read_text(d.file("whole.csv"));
  ASSERT_EQ(text.substr(text.size() - 4), "256\n");
  write_text(d.file("cut.csv"), text.substr(0, text.size() - 3));  // "...,2"
  const auto lines = std::count(text.begin(), text.end(), '\n');
  const auto r = run_cli({"calibrate", d.file("cut.csv")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(d.file("cut.csv") + ":" + std::to_string(lines) + ":"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("n_avg cannot be trusted"), std::string::npos) << r.err;
  // Without an n_avg column the row is kept, with a warning naming its line.
  std::string no_navg;
  for (std::size_t at = 0; at < text.size();) {
    const auto nl = text.find('\n', at);
    std::string line = text.substr(at, nl - at);
    if (!line.empty() && line[0] != '#') line = line.substr(0, line.rfind(','));
    no_navg += line + "\n";
    at = nl + 1;
  }
  no_navg.pop_back();
  write_text(d.file("open.csv"), no_navg);
  const auto w = run_cli({"calibrate", d.file("open.csv")});
  EXPECT_EQ(w.exit_code, 0) << w.err;
  EXPECT_NE(w.err.find("gyroflip: warning: " + d.file("open.csv") + ":" + std::to_string(lines) +
                       ": the file ends without a newline"),
            std::string::npos)
      << w.err;
  EXPECT_EQ(run_cli({"calibrate", d.file("whole.csv")}).err, "");
}

// Item 11: the same file given twice to calibrate was pooled twice (its standard error shrank by
// sqrt(2)); `adev --taus 1,10,1000` silently dropped 1000.
TEST(CliBadInput, SameRecordingTwiceAndDroppedFactorsAreSaid) {
  temp_dir d;
  simulated_recording(d.file("r.csv"));
  ::link(d.file("r.csv").c_str(), d.file("again.csv").c_str());
  for (const auto& second : {d.file("r.csv"), d.path() + "/./r.csv", d.file("again.csv")}) {
    const auto r = run_cli({"calibrate", d.file("r.csv"), second});
    EXPECT_EQ(r.exit_code, 2) << second;
    EXPECT_NE(r.err.find("is given twice"), std::string::npos) << r.err;
  }
  // 300 s at ~1.79 s per dwell pair: about 330 rows, so m = 1000 has no term.
  const auto a = run_cli({"adev", d.file("r.csv"), "--taus", "1,10,1000", "--json"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_NE(a.err.find("gyroflip: warning: " + d.file("r.csv") +
                       ": averaging factor 1000 dropped: oadev at tau = "),
            std::string::npos)
      << a.err;
  EXPECT_NE(a.out.find("\"dropped\":[{\"m\":1000,"), std::string::npos) << a.out;
}

// Issue 13 ("a user's first hour"): `noise` on a constant series said "noise fit needs at least 3
// Allan-deviation points with EDF >= 1" - true, but not what is wrong.
TEST(CliBadInput, ConstantSeriesSaysItIsConstant) {
  temp_dir d;
  std::string text = "time_s,rate_dps\n";
  for (int i = 0; i < 500; ++i) text += std::to_string(i) + ",0.5\n";
  write_text(d.file("c.csv"), text);
  const auto r = run_cli({"noise", d.file("c.csv")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(d.file("c.csv") + ": every Allan deviation is 0: the series is constant"),
            std::string::npos)
      << r.err;
  const auto a = run_cli({"adev", d.file("c.csv")});
  EXPECT_EQ(a.exit_code, 0);
  EXPECT_NE(a.err.find("the series is constant"), std::string::npos) << a.err;
}

// Review of issue 22, R10: `--seed -1` was wrapped to 18446744073709551615 and run. Every
// subcommand's --seed takes 0 .. 2^64 - 1 only: a negative, fractional or too large seed is a
// usage error (exit 2) naming the option, before anything runs or is written.
TEST(CliBadInput, ASeedIsAnIntegerFromZeroTo2To64) {
  temp_dir d;
  const std::vector<std::vector<std::string>> commands = {
      {"simulate", "--sensor", "hz1-90-100a", "--duration", "10", "-o", d.file("s.csv")},
      {"emulate", "--pty", "--duration", "1"},
      {"reproduce", "--quick"},
  };
  for (const auto& base : commands)
    for (const std::string seed : {"-1", "1.5", "-0", "18446744073709551616", "x"}) {
      auto cmd = base;
      cmd.insert(cmd.end(), {"--seed", seed});
      const auto r = run_cli(cmd);
      EXPECT_EQ(r.exit_code, 2) << cmd[0] << " --seed " << seed << ": " << r.err;
      EXPECT_NE(r.err.find("--seed"), std::string::npos) << cmd[0] << ": " << r.err;
    }
  EXPECT_FALSE(std::filesystem::exists(d.file("s.csv")));
  const auto top = run_cli({"simulate", "--sensor", "hz1-90-100a", "--duration", "10", "--seed",
                            "18446744073709551615", "-o", d.file("s.csv")});
  EXPECT_EQ(top.exit_code, 0) << top.err;
}

}  // namespace
}  // namespace gyroflip::test
