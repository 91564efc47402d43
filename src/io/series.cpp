/// \file
/// \brief Series readers: CSV column, NumPy .npy, raw float64 (see series.hpp).
#include "gyroflip/io/series.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "gyroflip/analysis/drift.hpp"
#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"
#include "gyroflip/io/compressed.hpp"
#include "gyroflip/io/csv.hpp"
#include "gyroflip/io/mapped_file.hpp"
#include "gyroflip/io/ros_bag.hpp"
#include "hdf5_series.hpp"

namespace gyroflip::io {
namespace {

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

status check_rate(const std::string& path, const std::optional<double>& rate_hz) {
  if (!rate_hz)
    return about_parameter(
        input_error({path}, "binary input has no time column: the sample rate must be given"),
        "sample_rate_hz");
  if (!(*rate_hz > 0.0) || !std::isfinite(*rate_hz))
    return parameter_error(
        "sample_rate_hz",
        fmt::format("the sample rate {} must be a positive number of samples per second",
                    *rate_hz));
  return ok();
}

// What a compressed binary file may decompress to (read whole into memory): 2^35 bytes, 4e9
// samples; beyond it a file is a decompression bomb or needs to be stored uncompressed.
constexpr std::size_t max_unpacked_bytes = std::size_t{1} << 35;

// Fewer samples than this give no deviation at all (two phase differences).
constexpr std::size_t min_samples = 3;

// The value of key `key` in a .npy header dict: the text after `'key':` up to the next top-level
// comma or the closing brace (a shape tuple's commas are inside parentheses).
std::optional<std::string_view> npy_value(std::string_view dict, std::string_view key) {
  const std::string quoted = fmt::format("'{}'", key);
  const auto at = dict.find(quoted);
  if (at == std::string_view::npos || dict.find(quoted, at + 1) != std::string_view::npos)
    return std::nullopt;  // absent or given twice
  std::size_t p = at + quoted.size();
  while (p < dict.size() && dict[p] == ' ') ++p;
  if (p >= dict.size() || dict[p] != ':') return std::nullopt;
  ++p;
  while (p < dict.size() && dict[p] == ' ') ++p;
  int depth = 0;
  std::size_t end = p;
  for (; end < dict.size(); ++end) {
    const char c = dict[end];
    if (c == '(') ++depth;
    if (c == ')') --depth;
    if (depth == 0 && (c == ',' || c == '}')) break;
  }
  std::string_view v = dict.substr(p, end - p);
  while (!v.empty() && v.back() == ' ') v.remove_suffix(1);
  return v;
}

// Where a .npy file's numbers are and how they are laid out.
struct npy_array {
  std::size_t offset = 0;  // of the data
  std::size_t rows = 0;    // samples
  std::size_t cols = 1;    // 1 for a 1-D array
  bool f4 = false;         // float32 ('<f4') rather than float64 ('<f8')
  bool fortran = false;    // column-major
};

// NumPy format 1.0-3.0 (numpy.lib.format): magic "\x93NUMPY", major, minor, header length (2
// bytes LE for 1.0, 4 for 2.0/3.0), then a Python dict literal with exactly the keys 'descr',
// 'fortran_order' and 'shape', padded with spaces and ended by '\n'; the data follow. Accepted:
// little-endian float64 ('<f8') or float32 ('<f4'), shape (N,) or (N, M) (samples x columns, as
// np.save writes a logger's table), the file holding exactly those values.
result<npy_array> npy_layout(const std::string& path, std::string_view d) {
  if (d.size() < 10 || d.substr(0, 6) != "\x93NUMPY")
    return input_error({path}, "not a NumPy .npy file (bad magic)");
  const auto major = static_cast<unsigned char>(d[6]);
  const auto minor = static_cast<unsigned char>(d[7]);
  if (major < 1 || major > 3 || minor != 0)
    return input_error({path}, fmt::format(".npy format version {}.{} is not supported (1.0, 2.0 "
                                           "or 3.0)",
                                           major, minor));
  const std::size_t len_bytes = major == 1 ? 2 : 4;
  if (d.size() < 8 + len_bytes) return input_error({path}, "truncated .npy header");
  std::size_t header_len = 0;
  for (std::size_t i = 0; i < len_bytes; ++i)
    header_len |= static_cast<std::size_t>(static_cast<unsigned char>(d[8 + i])) << (8 * i);
  const std::size_t start = 8 + len_bytes;
  if (header_len > d.size() - start)
    return input_error({path}, fmt::format("truncated .npy header ({} bytes announced, {} in the "
                                           "file)",
                                           header_len, d.size() - start));
  std::string_view h = d.substr(start, header_len);
  // The dict ends the header: '{', ..., '}', spaces, '\n'. A header length off by a few bytes
  // shows here (the last byte is then a data byte or part of the dict).
  if (h.empty() || h.back() != '\n')
    return input_error({path},
                       "malformed .npy header: it must end with a newline (wrong header "
                       "length?)");
  h.remove_suffix(1);
  while (!h.empty() && h.back() == ' ') h.remove_suffix(1);
  if (h.size() < 2 || h.front() != '{' || h.back() != '}')
    return input_error({path}, "malformed .npy header: not a dict literal");
  const auto descr = npy_value(h, "descr");
  const auto fortran = npy_value(h, "fortran_order");
  const auto shape = npy_value(h, "shape");
  if (!descr || !fortran || !shape)
    return input_error({path},
                       "malformed .npy header: needs 'descr', 'fortran_order' and "
                       "'shape', once each");
  npy_array a;
  if (*descr != "'<f8'" && *descr != "'<f4'")
    return input_error({path}, fmt::format(".npy dtype must be little-endian float64 '<f8' or "
                                           "float32 '<f4', not {}",
                                           printable(*descr)));
  a.f4 = *descr == "'<f4'";
  if (*fortran != "False" && *fortran != "True")
    return input_error({path}, "malformed .npy header: fortran_order must be True or False");
  a.fortran = *fortran == "True";
  // (N,) or (N, M) with N and M plain decimal integers; "(N)" is not a tuple.
  const std::string_view dims = *shape;
  const auto bad_shape = [&] {
    return input_error({path}, fmt::format(".npy array must be 1-D (N,) or 2-D (N, M); shape {}",
                                           printable(*shape)));
  };
  if (dims.size() < 3 || dims.front() != '(' || dims.back() != ')') return bad_shape();
  auto fields = text::split(dims.substr(1, dims.size() - 2), ',');
  const bool trailing_comma = fields.size() > 1 && fields.back().text.empty();
  if (trailing_comma) fields.pop_back();
  if (fields.size() > 2 || (fields.size() == 1 && !trailing_comma)) return bad_shape();
  std::uint64_t n[2] = {0, 1};
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const auto v = text::to_unsigned(fields[i].text);
    if (!v) return bad_shape();
    n[i] = *v;
  }
  const std::size_t size = a.f4 ? 4 : 8;
  const std::size_t data_bytes = d.size() - start - header_len;
  // The announced size in bytes, or none when it does not fit in 64 bits (a shape of 2^61
  // samples wrapped to "0 bytes" in the message).
  std::uint64_t values = 0, bytes = 0;
  const bool fits = !__builtin_mul_overflow(n[0], n[1], &values) &&
                    !__builtin_mul_overflow(values, std::uint64_t{size}, &bytes);
  if (n[1] == 0 || !fits || bytes != data_bytes)
    return input_error(
        {path},
        fmt::format(
            ".npy header announces {} ({}) but the file holds {} data bytes "
            "(truncated or padded file)",
            n[1] == 1 ? fmt::format("{} samples", n[0]) : fmt::format("{} x {} values", n[0], n[1]),
            fits ? fmt::format("{} bytes", bytes) : "more than 2^64 bytes", data_bytes));
  a.offset = start + header_len;
  a.rows = static_cast<std::size_t>(n[0]);
  a.cols = static_cast<std::size_t>(n[1]);
  return a;
}

// A column number from 1 ("3") as a 0-based index; nullopt for a name.
std::optional<std::size_t> column_number(std::string_view name) {
  const auto k = text::to_unsigned(name);
  if (!k || *k == 0) return std::nullopt;
  return static_cast<std::size_t>(*k - 1);
}

// Little-endian float64 samples of a mapped file from byte `offset` (8-byte aligned, checked by
// the caller), which it owns. Released samples' pages leave the process.
class mapped_samples final : public mapping_samples {
 public:
  mapped_samples(mapped_file file, std::size_t offset, std::size_t count)
      // cppcheck-suppress invalidPointerCast ; mapped little-endian float64, alignment checked
      : mapping_samples(reinterpret_cast<const double*>(file.data().data() + offset),  // NOLINT
                        count),
        file_(std::move(file)) {}

 private:
  mapped_file file_;  // the mapping stays where it is when moved here
};

// An error at data row `row` (0-based) of CSV `path`, column `column`: reads the file again up to
// that row (only on this error path) for its line and column.
error at_row(const std::string& path, const csv_dialect& dialect, std::size_t column,
             std::size_t row, std::string_view what) {
  auto r = csv_reader::open(path, dialect);
  if (!r) return input_error({path}, what);
  r->select({column});
  for (std::size_t k = 0; k <= row; ++k)
    if (r->next() != csv_reader::step::row) return input_error({path}, what);
  return r->error_at(0, what);
}

}  // namespace

void series::hold(std::vector<double> values) {
  owned_ = std::move(values);
  samples_ = std::make_unique<analysis::span_samples>(owned_);
}

namespace {

// The interval comes from the whole record; each stamp may be rounded or jittered by up to half
// an interval, but a gap or a duplicate breaks the uniform grid the deviations assume.
struct grid {
  double step = 0.0;
  std::optional<std::size_t> bad;  // the first sample off the grid
  double off = 0.0;
};

grid uniform_grid(std::span<const double> t) {
  grid g;
  g.step = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double off = t[k] - (t.front() + static_cast<double>(k) * g.step);
    if (std::abs(off) > 0.5 * g.step) {
      g.bad = k;
      g.off = off;
      return g;
    }
  }
  return g;
}

std::string off_grid_message(std::span<const double> t, const grid& g) {
  return fmt::format(
      "sample {} (time_s {}) is {:.3g} s off the uniform grid of {:.6g} s: the record has a gap "
      "or uneven sampling (resample, or give the sample rate)",
      *g.bad + 1, t[*g.bad], g.off, g.step);
}

// A time stamp's integer part: 128 bits, so that stamps past int64 (9.2e18: nanoseconds after
// the year 2262, or a logger counting picoseconds) are still rebased exactly (issue 21: a stamp
// past int64 fell back to a double and was reported as "does not increase").
__extension__ using stamp_int = __int128;
constexpr std::size_t max_stamp_digits = 38;  // 10^38 - 1 < 2^127

enum class stamp_form { plain, other, too_long };

// A time stamp split into its integer part and its fraction, so that epoch stamps (1.7e9 s,
// 1.7e18 ns) are rebased exactly before any floating-point arithmetic: [sign]digits[.digits]
// with the dialect's decimal mark. `other` for other forms (exponents), which are read as
// doubles; `too_long` for an integer part of more than 38 digits.
stamp_form split_stamp(std::string_view s, char decimal, stamp_int& whole, double& frac) {
  std::size_t i = 0;
  const bool negative = !s.empty() && s[0] == '-';
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) ++i;
  const std::size_t int_begin = i;
  stamp_int w = 0;
  for (; i < s.size() && s[i] >= '0' && s[i] <= '9'; ++i) {
    if (i - int_begin == max_stamp_digits) return stamp_form::too_long;
    w = 10 * w + (s[i] - '0');
  }
  if (i == int_begin) return stamp_form::other;
  double f = 0.0;
  if (i < s.size()) {
    if (s[i] != decimal) return stamp_form::other;
    const std::size_t frac_begin = ++i;
    while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
    if (i != s.size() || i == frac_begin) return stamp_form::other;
    char buf[48] = "0.";
    const std::size_t digits = std::min<std::size_t>(i - frac_begin, sizeof buf - 3);
    std::memcpy(buf + 2, s.data() + frac_begin, digits);
    std::from_chars(buf, buf + 2 + digits, f);
  }
  whole = negative ? -w : w;
  frac = negative ? -f : f;
  return stamp_form::plain;
}

// The samples of a CSV time column that form the analysed run, and its period.
struct stamp_run {
  std::size_t begin = 0, end = 0;  // samples [begin, end)
  double tau0_s = 0.0;
  std::vector<std::string> notes;
  // gap_policy::fill: after sample k, so many samples interpolated (k ascending).
  std::vector<std::pair<std::size_t, std::size_t>> fills;
};

// `v` with the samples `fills` bridges: each gap's samples on the straight line between the
// samples before and after it.
void fill_gaps(std::vector<double>& v,
               const std::vector<std::pair<std::size_t, std::size_t>>& fills, bool as_nan = false) {
  if (fills.empty()) return;
  std::size_t extra = 0;
  for (const auto& f : fills) extra += f.second;
  std::vector<double> out;
  out.reserve(v.size() + extra);
  std::size_t next = 0;
  for (const auto& [k, m] : fills) {
    out.insert(out.end(), v.begin() + static_cast<std::ptrdiff_t>(next),
               v.begin() + static_cast<std::ptrdiff_t>(k + 1));
    for (std::size_t j = 1; j <= m; ++j)
      out.push_back(as_nan ? std::numeric_limits<double>::quiet_NaN()
                           : v[k] + (v[k + 1] - v[k]) * static_cast<double>(j) /
                                        static_cast<double>(m + 1));
    next = k + 1;
  }
  out.insert(out.end(), v.begin() + static_cast<std::ptrdiff_t>(next), v.end());
  v = std::move(out);
}

// Gaps, jitter and the rate of time stamps `t` (s from the first; strictly increasing).
// `row_error(k, what)` locates a message at sample k's time cell.
template <class RowError>
result<stamp_run> check_stamps(const std::string& path, std::span<const double> t,
                               const series_options& opt, const RowError& row_error) {
  const std::size_t n = t.size();
  std::vector<double> d(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k) d[k] = t[k + 1] - t[k];
  const double period = analysis::upper_median(d);
  std::vector<std::size_t> gaps;  // k: a gap between samples k and k + 1
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (d[k] < 0.5 * period)
      return row_error(k + 1, fmt::format("sample {} comes {:.6g} s after the previous one, less "
                                          "than half the period {:.6g} s: duplicated or uneven "
                                          "time stamps",
                                          k + 2, d[k], period));
    if (d[k] > 1.5 * period) gaps.push_back(k);
  }
  const auto describe = [&](std::size_t k) {
    // In floating point: a wild stamp makes the ratio too large for any integer type.
    const double missing = std::round(d[k] / period) - 1.0;
    return fmt::format(
        "after sample {} (time {:.6g} s) the next comes {:.6g} s later, about "
        "{:.6g} sample{} missing",
        k + 1, t[k], d[k], missing, missing == 1.0 ? "" : "s");
  };
  stamp_run run{0, n, 0.0, {}, {}};
  if (!gaps.empty() && opt.gaps == gap_policy::error) {
    std::string list;
    for (std::size_t i = 0; i < std::min<std::size_t>(gaps.size(), 3); ++i)
      list += (i == 0 ? "" : "; ") + describe(gaps[i]);
    if (gaps.size() > 3) list += fmt::format("; and {} more", gaps.size() - 3);
    return about_parameter(
        row_error(gaps[0] + 1,
                  fmt::format("the time stamps have {} gap{} (period {:.6g} s): {}. Deviations "
                              "need evenly spaced samples: bridge short gaps (fill: at most 1 % "
                              "of the samples interpolated), analyse the longest gap-free run "
                              "(split), or resample",
                              gaps.size(), gaps.size() == 1 ? "" : "s", period, list)),
        "gaps");
  }
  // gap_policy::fill: each sample's place on the grid counts the samples bridged before it.
  std::vector<std::size_t> place;
  if (!gaps.empty() && opt.gaps == gap_policy::fill) {
    double missing = 0.0, most = 0.0;
    std::size_t longest = gaps[0];
    // The samples bridged in gap k: at least one (a gap is over 1.5 periods).
    const auto bridged = [&](std::size_t k) {
      return std::max(1.0, std::round(d[k] / period) - 1.0);
    };
    for (const auto k : gaps) {
      const double m = bridged(k);
      missing += m;
      if (m > most) {
        most = m;
        longest = k;
      }
    }
    const double share = missing / (missing + static_cast<double>(n));
    if (!(share <= max_filled_fraction))
      return about_parameter(
          row_error(gaps[0] + 1,
                    fmt::format("the time stamps' {} gap{} miss {:.6g} samples, {:.3g} % of the "
                                "record: more than {:g} % is not bridged (first: {}). Analyse the "
                                "longest gap-free run (split), or resample",
                                gaps.size(), gaps.size() == 1 ? "" : "s", missing, 100.0 * share,
                                100.0 * max_filled_fraction, describe(gaps[0]))),
          "gaps_split");
    place.resize(n);
    std::size_t added = 0, g = 0;
    for (std::size_t k = 0; k < n; ++k) {
      place[k] = k + added;
      if (g < gaps.size() && gaps[g] == k) {
        const auto m = static_cast<std::size_t>(bridged(k));
        run.fills.emplace_back(k, m);
        added += m;
        ++g;
      }
    }
    run.notes.push_back(
        fmt::format("the time stamps have {} gap{}; {} sample{} ({:.3g} % of {}) bridged by linear "
                    "interpolation; the longest: {}",
                    gaps.size(), gaps.size() == 1 ? "" : "s", added, added == 1 ? "" : "s",
                    100.0 * share, n + added, describe(longest)));
  } else if (!gaps.empty()) {
    std::size_t from = 0;
    run.end = 0;
    for (std::size_t i = 0; i <= gaps.size(); ++i) {
      const std::size_t to = i < gaps.size() ? gaps[i] + 1 : n;
      if (to - from > run.end - run.begin) run = {from, to, 0.0, {}, {}};
      from = to;
    }
    if (run.end - run.begin < min_samples)
      return input_error({path}, fmt::format("no gap-free run of {} samples or more in the time "
                                             "stamps ({} gaps)",
                                             min_samples, gaps.size()));
    run.notes.push_back(fmt::format(
        "the time stamps have {} gap{} (first: {}); analysed: samples {} to {} (time {:.6g} to "
        "{:.6g} s), the longest of {} gap-free runs",
        gaps.size(), gaps.size() == 1 ? "" : "s", describe(gaps[0]), run.begin + 1, run.end,
        t[run.begin], t[run.end - 1], gaps.size() + 1));
  }
  const auto at = [&](std::size_t k) {
    return static_cast<double>(place.empty() ? k - run.begin : place[k]);
  };
  run.tau0_s = (t[run.end - 1] - t[run.begin]) / at(run.end - 1);
  double jitter = 0.0;
  for (std::size_t k = run.begin; k < run.end; ++k) {
    const double off = t[k] - (t[run.begin] + at(k) * run.tau0_s);
    if (std::abs(off) > 0.5 * run.tau0_s)
      return row_error(k, fmt::format("sample {} (time {:.6g} s) is {:.3g} s off the uniform grid "
                                      "of {:.6g} s: the sample clock drifts or the rate changes",
                                      k + 1, t[k], off, run.tau0_s));
    if (k + 1 < run.end && at(k + 1) - at(k) == 1.0)
      jitter = std::max(jitter, std::abs(d[k] - run.tau0_s) / run.tau0_s);
  }
  if (jitter > 1e-3)
    run.notes.push_back(
        fmt::format("the time stamps jitter by up to {:.3g} % of the period {:.6g} "
                    "s (accepted below 50 %; the deviations assume the mean "
                    "period)",
                    100.0 * jitter, run.tau0_s));
  if (opt.sample_rate_hz) {
    if (auto c = check_rate(path, opt.sample_rate_hz); !c) return c.err();
    const double stamped_hz = 1.0 / run.tau0_s;
    if (std::abs(*opt.sample_rate_hz - stamped_hz) > 0.01 * stamped_hz)
      return about_parameter(
          input_error({path}, fmt::format("the sample rate {:.6g} Hz disagrees with the time "
                                          "stamps' {:.6g} Hz by more than 1 %",
                                          *opt.sample_rate_hz, stamped_hz)),
          "sample_rate_hz");
    run.tau0_s = 1.0 / *opt.sample_rate_hz;
  }
  return run;
}

// A CSV column, with its time column (or the given rate) and a recording's angle_deg.
struct csv_series {
  std::vector<std::vector<double>> values;  // per column asked for
  std::vector<double> angle_deg;
  double tau0_s = 0.0;
  std::vector<csv_metadata> metadata;
  std::vector<std::string> notes;
  std::string topic;  // a ROS bag's
};

// The time column asked for, or time_s when the file has one.
result<std::optional<std::size_t>> time_column_of(const csv_reader& r, const series_options& opt) {
  if (opt.time_column.empty()) return r.find_column("time_s");
  auto t = r.require_column(opt.time_column);
  if (!t) return t.err();
  return std::optional<std::size_t>(*t);
}

// CSV columns (one pass over the file), with the time column (or the given rate) and a
// recording's angle_deg. Selected cells: 0 time, 1 angle, 2... the columns.
result<csv_series> read_csv_series(const std::string& path, const series_options& opt,
                                   const std::vector<std::string>& columns) {
  csv_series s;
  auto r = csv_reader::open(path, opt.dialect);
  if (!r) return r.err();
  std::vector<std::size_t> cols;
  for (const auto& name : columns) {
    auto c = r->require_column(name);
    if (!c) return c.err();
    cols.push_back(*c);
  }
  auto time = time_column_of(*r, opt);
  if (!time) return time.err();
  if (!*time && !opt.sample_rate_hz)
    return about_parameter(
        input_error({path}, "no time column (time_s, or name one): the sample rate must be given"),
        "sample_rate_hz");
  // A recording's angle_deg (0, 180, empty while turning) goes along, so that the caller can tell
  // an uncompensated flip recording (method/flip_detect.hpp).
  auto angle = r->find_column("angle_deg");
  if (!angle) return angle.err();
  const bool with_angle =
      angle->has_value() && std::find(cols.begin(), cols.end(), **angle) == cols.end();
  std::vector<std::size_t> selected{*time ? **time : csv_reader::absent_column,
                                    with_angle ? **angle : csv_reader::absent_column};
  selected.insert(selected.end(), cols.begin(), cols.end());
  r->select(selected);
  const char decimal = r->dialect().decimal;
  std::vector<double> t;
  s.values.resize(cols.size());
  // Standard input cannot be read again to locate a row in a message: keep each row's line.
  const bool rereadable = path != "-";
  std::vector<std::size_t> lines;
  stamp_int whole0 = 0;
  double frac0 = 0.0;
  while (true) {
    const auto st = r->next();
    if (st == csv_reader::step::end) break;
    if (st == csv_reader::step::failed) return r->last_error();
    for (std::size_t c = 0; c < cols.size(); ++c) {
      double v = 0.0;
      if (!r->parse(2 + c, v)) return r->last_error();
      s.values[c].push_back(v);
    }
    if (*time) {
      stamp_int whole = 0;
      double frac = 0.0;
      const stamp_form form = split_stamp(r->cell(0), decimal, whole, frac);
      if (form == stamp_form::too_long)
        return r->error_at(0, fmt::format("time stamp {} has more than {} digits before the "
                                          "decimal mark: use a coarser time unit",
                                          printable(r->cell(0), 60), max_stamp_digits));
      if (form == stamp_form::other) {
        if (!r->parse(0, frac)) return r->last_error();
        whole = 0;
      }
      if (t.empty()) {
        whole0 = whole;
        frac0 = frac;
      }
      // Rebased before scaling: the difference of two epoch stamps is exact in 128 bits.
      stamp_int since = 0;
      if (__builtin_sub_overflow(whole, whole0, &since))
        return r->error_at(0, fmt::format("time stamp {} is too far from the first one",
                                          printable(r->cell(0), 40)));
      const double ts = (static_cast<double>(since) + (frac - frac0)) * opt.time_unit_s;
      if (!t.empty() && !(ts > t.back()))
        return r->error_at(0, fmt::format("time stamp {} does not increase", r->cell(0)));
      t.push_back(ts);
      if (!rereadable) lines.push_back(r->line());
    }
    if (with_angle) {
      double a = std::numeric_limits<double>::quiet_NaN();  // empty: the table is turning
      if (!r->cell(1).empty() && !r->parse(1, a)) return r->last_error();
      s.angle_deg.push_back(a);
    }
  }
  s.metadata = r->metadata();  // after the rows: metadata may follow the header
  const std::size_t n = s.values.front().size();
  if (n < min_samples)
    return input_error({path}, fmt::format("{} sample{}: too few for an analysis (at least {})", n,
                                           n == 1 ? "" : "s", min_samples));
  if (!*time) {
    if (auto c = check_rate(path, opt.sample_rate_hz); !c) return c.err();
    s.tau0_s = 1.0 / *opt.sample_rate_hz;
    return s;
  }
  const auto row_error = [&](std::size_t k, std::string_view what) {
    if (!rereadable) return input_error({"<stdin>", lines[k]}, what);
    return at_row(path, opt.dialect, **time, k, what);
  };
  auto run = check_stamps(path, std::span<const double>(t), opt, row_error);
  if (!run) return run.err();
  const auto cut = [&](std::vector<double>& v) {
    if (run->begin != 0 || run->end != v.size())
      v = std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(run->begin),
                              v.begin() + static_cast<std::ptrdiff_t>(run->end));
  };
  for (auto& v : s.values) {
    cut(v);
    fill_gaps(v, run->fills);
  }
  if (with_angle) {
    cut(s.angle_deg);
    fill_gaps(s.angle_deg, run->fills, true);  // not measured: no position
  }
  s.tau0_s = run->tau0_s;
  s.notes = std::move(run->notes);
  return s;
}

// Columns of a ROS bag's IMU topic (io/ros_bag.hpp), on its header stamps, with the time
// checks of a CSV's time column; errors name the message.
result<csv_series> read_bag_series(const std::string& path, const series_options& opt,
                                   const std::vector<std::string>& columns) {
  auto table = read_imu_bag(path, opt.topic);
  if (!table) return table.err();
  std::vector<std::string> names(imu_columns.begin(), imu_columns.end());
  std::vector<std::size_t> picked;
  for (const auto& name : columns) {
    std::optional<std::size_t> c;
    for (std::size_t i = 0; i < imu_columns.size(); ++i)
      if (name == imu_columns[i] || name == imu_fields[i]) c = i;
    if (const auto k = column_number(name); !c && k && *k < imu_columns.size()) c = *k;
    if (!c) {
      const std::string near = did_you_mean(name, names);
      return about_parameter(
          input_error({path},
                      fmt::format("topic {} has no column '{}'{} (its columns: {}; or the "
                                  "message fields {})",
                                  printable(table->topic, 100), printable(name),
                                  near.empty() ? "" : fmt::format(": did you mean '{}'?", near),
                                  fmt::join(imu_columns, ", "), fmt::join(imu_fields, ", "))),
          "column");
    }
    picked.push_back(*c);
  }
  csv_series s;
  const std::size_t n = table->time_s.size();
  if (n < min_samples)
    return input_error(
        {path}, fmt::format("topic {}: {} message{}, too few for an analysis (at "
                            "least {})",
                            printable(table->topic, 100), n, n == 1 ? "" : "s", min_samples));
  const auto row_error = [&](std::size_t k, std::string_view what) {
    return input_error(
        {path}, fmt::format("message {} on {}: {}", k + 1, printable(table->topic, 100), what));
  };
  auto run = check_stamps(path, std::span<const double>(table->time_s), opt, row_error);
  if (!run) return run.err();
  for (const auto c : picked) {
    auto& v = table->values[c];
    std::vector<double> one(v.begin() + static_cast<std::ptrdiff_t>(run->begin),
                            v.begin() + static_cast<std::ptrdiff_t>(run->end));
    fill_gaps(one, run->fills);
    s.values.push_back(std::move(one));
  }
  s.tau0_s = run->tau0_s;
  s.topic = table->topic;
  s.notes = std::move(run->notes);
  s.notes.insert(s.notes.begin(), fmt::format("topic {}: {} sensor_msgs/Imu messages",
                                              printable(table->topic, 100), n));
  return s;
}

// `FILE.h5:/dataset` or `FILE.bag:/topic` split into the file and what it names inside (empty
// for other names). Bags also compressed (FILE.bag.gz:/topic).
std::pair<std::string, std::string> split_dataset(const std::string& spec) {
  for (const std::string_view ext : {".h5", ".hdf5", ".hdf", ".bag", ".db3"}) {
    for (const std::string_view packed : {"", ".gz", ".xz", ".zst"}) {
      if (!packed.empty() && (ext == ".h5" || ext == ".hdf5" || ext == ".hdf")) continue;
      const std::string mark = std::string(ext) + std::string(packed) + ":";
      const auto at = spec.find(mark);
      if (at != std::string::npos)
        return {spec.substr(0, at + mark.size() - 1), spec.substr(at + mark.size())};
    }
  }
  return {spec, {}};
}

// What read_series takes `path` for, by its name: HDF5 (`FILE.h5:/dataset`, or FILE.h5 with the
// `dataset` option), a ROS bag (`FILE.bag:/topic`, .db3), .npy, raw float64, else CSV; each
// but HDF5 may be compressed (.gz, .xz, .zst). `path` and `dataset` or `topic` are split.
// Errors: the name and the dataset or topic option name two different things.
enum class series_format { csv, hdf5, npy, raw, bag };
result<series_format> format_of(std::string& path, std::string& dataset, std::string& topic) {
  auto [file, named] = split_dataset(path);
  const bool bag = is_ros_bag(file);
  if (!named.empty()) {
    // `FILE.h5:/a` with the dataset parameter `/b`: which one was meant cannot be guessed.
    std::string& given = bag ? topic : dataset;
    if (!given.empty() && given != named)
      return about_parameter(
          input_error({path}, fmt::format("names {} '{}', but the {} parameter says '{}': give it "
                                          "once",
                                          bag ? "topic" : "dataset", printable(named, 120),
                                          bag ? "topic" : "dataset", printable(given, 120))),
          bag ? "topic" : "dataset");
    path = std::move(file);
    given = std::move(named);
  }
  if (bag) return series_format::bag;
  // The format inside a compressed file (a.npy.gz) is its name's without the compression.
  const std::string_view inner = without_compression(path);
  if (!dataset.empty() || ends_with(inner, ".h5") || ends_with(inner, ".hdf5")) {
    if (inner.size() != path.size())
      return input_error({path},
                         "a compressed HDF5 file cannot be read directly: HDF5 "
                         "compresses inside the file (its gzip filter); decompress it "
                         "first");
    return series_format::hdf5;
  }
  if (ends_with(inner, ".npy")) return series_format::npy;
  if (ends_with(inner, ".f64") || ends_with(inner, ".bin") || ends_with(inner, ".raw"))
    return series_format::raw;
  return series_format::csv;
}

}  // namespace

std::string series_file(const std::string& spec) {
  return split_dataset(spec).first;
}

result<series> read_series(const std::string& path_in, const series_options& opt) {
  series s;
  s.source_ = path_in;
  std::string path = path_in;
  std::string dataset = opt.dataset, topic = opt.topic;
  const auto known = format_of(path, dataset, topic);
  if (!known) return known.err();
  const series_format format = *known;
  if (format == series_format::bag) {
    auto all = read_series_columns(path_in, opt, {opt.column});
    if (!all) return all.err();
    series one = std::move(all->front());
    return one;
  }
  if (format == series_format::hdf5) {
    if (dataset.empty())
      return about_parameter(
          input_error({path}, "name the dataset, as FILE.h5:/path or as the dataset parameter"),
          "dataset");
    auto h = detail::read_hdf5_dataset(path, dataset, column_number(opt.column));
    if (!h) return h.err();
    if (!opt.sample_rate_hz && !h->sample_rate_hz)
      return about_parameter(
          input_error({path}, fmt::format("dataset '{}' has no sample_rate_hz attribute: the "
                                          "sample rate must be given",
                                          printable(dataset, 120))),
          "sample_rate_hz");
    // A rate from the file that is no rate is the file's fault, not the parameter's (which was
    // not given).
    if (!opt.sample_rate_hz && !(*h->sample_rate_hz > 0.0 && std::isfinite(*h->sample_rate_hz)))
      return input_error({path}, fmt::format("dataset '{}': its sample_rate_hz attribute is {}, "
                                             "not a sample rate (a positive number of samples "
                                             "per second); give the sample rate instead",
                                             printable(dataset, 120), *h->sample_rate_hz));
    const auto rate = opt.sample_rate_hz ? opt.sample_rate_hz : h->sample_rate_hz;
    if (auto c = check_rate(path, rate); !c) return c.err();
    for (std::size_t i = 0; i < h->values.size(); ++i)
      if (!std::isfinite(h->values[i]))
        return input_error({path}, fmt::format("{}[{}] is not finite", dataset, i));
    if (h->values.size() < 3)
      return input_error({path},
                         fmt::format("{}: {} samples are too few", dataset, h->values.size()));
    s.hold(std::move(h->values));
    s.tau0_s_ = 1.0 / *rate;
    return s;
  }
  const bool npy = format == series_format::npy;
  if (npy || format == series_format::raw) {
    if (auto r = check_rate(path, opt.sample_rate_hz); !r) return r.err();
    // A compressed file is decompressed into memory (8 bytes a sample), a plain one mapped.
    const bool packed = compression_of(path) != compression::none;
    std::optional<mapped_file> f;
    std::vector<char> unpacked;
    std::string_view data;
    if (packed) {
      auto u = read_decompressed(path, max_unpacked_bytes);
      if (!u) return u.err();
      unpacked = std::move(*u);
      data = {unpacked.data(), unpacked.size()};
    } else {
      auto m = mapped_file::open(path);
      if (!m) return m.err();
      f.emplace(std::move(*m));
      data = f->data();
    }
    std::size_t offset = 0;
    std::size_t count = 0;
    if (npy) {
      auto layout = npy_layout(path, data);
      if (!layout) return layout.err();
      if (layout->f4 || layout->cols > 1) {
        // float32 or one column of a table: converted once into memory (8 bytes a sample).
        const auto col = column_number(opt.column);
        if (layout->cols > 1 && (!col || *col >= layout->cols))
          return about_parameter(
              input_error({path}, fmt::format(".npy array has {} columns: give a column number "
                                              "from 1 to {}",
                                              layout->cols, layout->cols)),
              "column");
        if (layout->rows < min_samples)
          return input_error({path}, fmt::format("{} samples: too few for an analysis (at least "
                                                 "{})",
                                                 layout->rows, min_samples));
        std::vector<double> v(layout->rows);
        const std::size_t c = layout->cols > 1 ? *col : 0;
        const char* base = data.data() + layout->offset;
        for (std::size_t r = 0; r < layout->rows; ++r) {
          const std::size_t k = layout->fortran ? c * layout->rows + r : r * layout->cols + c;
          if (layout->f4) {
            float x = 0.0F;
            std::memcpy(&x, base + k * sizeof x, sizeof x);
            v[r] = static_cast<double>(x);
          } else {
            std::memcpy(&v[r], base + k * sizeof(double), sizeof(double));
          }
        }
        s.hold(std::move(v));
        s.tau0_s_ = 1.0 / *opt.sample_rate_hz;
        return s;
      }
      offset = layout->offset;
      count = layout->rows;
    } else {
      const std::size_t bytes = data.size();
      if (bytes % sizeof(double) != 0)
        return input_error({path},
                           fmt::format("{} bytes are not a whole number of float64 values", bytes));
      count = bytes / sizeof(double);
    }
    if (count < min_samples)
      return input_error({path}, fmt::format("{} sample{}: too few for an analysis (at least {})",
                                             count, count == 1 ? "" : "s", min_samples));
    static_assert(std::endian::native == std::endian::little,
                  "raw and .npy readers assume a little-endian host");
    if (packed) {
      std::vector<double> v(count);
      std::memcpy(v.data(), data.data() + offset, count * sizeof(double));
      s.hold(std::move(v));
      s.tau0_s_ = 1.0 / *opt.sample_rate_hz;
      return s;
    }
    const char* p = data.data() + offset;
    if (reinterpret_cast<std::uintptr_t>(p) % alignof(double) != 0)  // NOLINT: checking alignment
      return input_error({path}, "float64 data are not 8-byte aligned in the file");
    // Not read here: phase_source::make checks every sample (finite) as it passes over them.
    s.samples_ = std::make_unique<mapped_samples>(std::move(*f), offset, count);  // NOLINT
    s.tau0_s_ = 1.0 / *opt.sample_rate_hz;
    return s;
  }
  auto all = read_series_columns(path, opt, {opt.column});
  if (!all) return all.err();
  series one = std::move(all->front());
  return one;
}

result<std::vector<series>> read_series_columns(const std::string& path, const series_options& opt,
                                                const std::vector<std::string>& columns) {
  if (columns.empty()) return parameter_error("columns", "no column to read");
  std::string file = path, dataset = opt.dataset, topic = opt.topic;
  const auto known = format_of(file, dataset, topic);
  if (!known) return known.err();
  if (*known != series_format::csv && *known != series_format::bag)
    return input_error({path}, "several columns: a CSV file or a ROS bag only");
  series_options bag_opt = opt;
  bag_opt.topic = topic;
  auto c = *known == series_format::bag ? read_bag_series(file, bag_opt, columns)
                                        : read_csv_series(path, opt, columns);
  if (!c) return c.err();
  std::vector<series> out;
  for (auto& v : c->values) {
    series s;
    s.source_ = path;
    s.hold(std::move(v));
    s.tau0_s_ = c->tau0_s;
    s.angle_deg_ = c->angle_deg;
    s.metadata_ = c->metadata;
    s.notes_ = c->notes;
    s.topic_ = c->topic;
    out.push_back(std::move(s));
  }
  return out;
}

result<std::vector<std::string>> numeric_columns(const std::string& path,
                                                 const series_options& opt) {
  if (path == "-")
    return input_error({"<stdin>"},
                       "the numeric columns of standard input cannot be found "
                       "before it is read: name the columns");
  if (is_ros_bag(split_dataset(path).first))  // every sensor_msgs/Imu axis
    return std::vector<std::string>(imu_columns.begin(), imu_columns.end());
  auto r = csv_reader::open(path, opt.dialect);
  if (!r) return r.err();
  auto time = time_column_of(*r, opt);
  if (!time) return time.err();
  std::vector<std::size_t> all(r->header().size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  r->select(all);
  const auto st = r->next();
  if (st == csv_reader::step::failed) return r->last_error();
  if (st == csv_reader::step::end) return input_error({path}, "no data rows after the header");
  std::vector<std::string> names;
  for (std::size_t i = 0; i < all.size(); ++i) {
    double v = 0.0;
    if (*time && **time == i) continue;
    if (r->header()[i] == "angle_deg") continue;  // a flip recording's table angle
    if (r->parse(i, v)) names.push_back(r->header()[i]);
  }
  if (names.empty())
    return input_error({path}, "no numeric column besides the time stamps in the first data row");
  return names;
}

result<series> series_of_samples(std::string source, std::vector<double> values,
                                 std::span<const double> time_s, std::vector<double> angle_deg,
                                 std::vector<csv_metadata> metadata) {
  if (values.size() < min_samples)
    return input_error(
        {source}, fmt::format("{} sample{}: too few for an analysis (at least {})", values.size(),
                              values.size() == 1 ? "" : "s", min_samples));
  const auto g = uniform_grid(time_s);
  if (g.bad) return input_error({source}, off_grid_message(time_s, g));
  series s;
  s.source_ = std::move(source);
  s.hold(std::move(values));
  s.tau0_s_ = g.step;
  s.angle_deg_ = std::move(angle_deg);
  s.metadata_ = std::move(metadata);
  return s;
}

}  // namespace gyroflip::io
