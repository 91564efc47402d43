/// \file
/// \brief Strict CSV reader, a block at a time (see csv.hpp).
#include "gyroflip/io/csv.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"

namespace gyroflip::io {
namespace {

// A single line longer than this is not a recording row; stop early instead of scanning on.
constexpr std::size_t max_line_bytes = std::size_t{1} << 20;
constexpr std::size_t binary_probe_bytes = std::size_t{64} << 10;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool is_blank(std::string_view s) {
  return trim(s).empty();
}

// Calls field(begin, end) with the byte offsets of each field of `line`. With blanks as the
// delimiter, runs of spaces and tabs separate fields and those at the ends are not fields;
// otherwise every delimiter byte ends a field (a line without one is one field).
template <class F>
void for_each_field(std::string_view line, char delimiter, F&& field) {
  const char* const base = line.data();
  const std::size_t size = line.size();
  if (delimiter == ' ') {
    const auto blank = [&](std::size_t i) { return base[i] == ' ' || base[i] == '\t'; };
    for (std::size_t i = 0;;) {
      while (i < size && blank(i)) ++i;
      if (i == size) return;
      const std::size_t begin = i;
      while (i < size && !blank(i)) ++i;
      field(begin, i);
    }
  }
  std::size_t start = 0;
  // Eight bytes at a time: t has 0x80 exactly in the bytes equal to the delimiter (no false
  // positives, unlike the shorter (x - 0x01..) & ~x form), then each set bit is one field end.
  constexpr std::uint64_t low7 = 0x7F7F7F7F7F7F7F7Full;
  const std::uint64_t delims = 0x0101010101010101ull * static_cast<unsigned char>(delimiter);
  std::size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, base + i, 8);
    const std::uint64_t x = w ^ delims;
    std::uint64_t t = ~(((x & low7) + low7) | x | low7);
    while (t != 0) {
      const std::size_t end = i + static_cast<std::size_t>(std::countr_zero(t)) / 8;
      field(start, end);
      start = end + 1;
      t &= t - 1;
    }
  }
  for (; i < size; ++i)
    if (base[i] == delimiter) {
      field(start, i);
      start = i + 1;
    }
  field(start, size);
}

}  // namespace

std::string delimiter_name(char delimiter) {
  switch (delimiter) {
    case '\t':
      return "tab";
    case ' ':
      return "blanks";
    default:
      return fmt::format("'{}'", delimiter);
  }
}

result<csv_reader> csv_reader::open(const std::string& path, const csv_dialect& dialect) {
  if (dialect.decimal != '.' && dialect.decimal != ',')
    return parameter_error("decimal", "the decimal mark must be '.' or ','");
  if (dialect.delimiter != 0 && dialect.delimiter != ',' && dialect.delimiter != ';' &&
      dialect.delimiter != '\t' && dialect.delimiter != ' ')
    return parameter_error("delimiter", "the delimiter must be ',', ';', tab or blanks");
  if (dialect.decimal == ',' && dialect.delimiter == ',')
    return parameter_error("decimal", "a decimal comma needs another delimiter than ','");
  csv_reader r = path == "-" ? csv_reader(owned_fd(), "<stdin>", 0) : csv_reader({}, path, 0);
  if (path != "-") {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return io_error(path, std::strerror(errno));
    r.fd_ = owned_fd(fd);
    struct stat st {};
    if (::fstat(fd, &st) != 0) return io_error(path, std::strerror(errno));
    if (S_ISDIR(st.st_mode)) return io_error(path, "is a directory, not a file");
    if (!S_ISREG(st.st_mode)) return io_error(path, "not a regular file");
    r.size_bytes_ = static_cast<std::uint64_t>(st.st_size);
    ::posix_fadvise(fd, 0, 0, POSIX_FADV_SEQUENTIAL);
  }
  r.dialect_ = dialect;
  while (r.buf_len_ < binary_probe_bytes && r.refill()) {
  }
  const std::string_view d(r.buf_.get(), r.buf_len_);
  const bool from_stdin = path == "-";
  if (d.empty())
    return input_error({r.path_}, from_stdin ? "empty input (expected a CSV header line)"
                                             : "empty file (expected a CSV header line)");
  if (std::memchr(d.data(), '\0', std::min(d.size(), binary_probe_bytes)) != nullptr)
    return input_error({r.path_}, from_stdin ? "binary data (NUL byte), not a UTF-8 CSV text"
                                             : "binary data (NUL byte), not a UTF-8 CSV text file");
  if (d.substr(0, 3) == "\xEF\xBB\xBF") r.buf_pos_ = r.pos_ = 3;  // UTF-8 byte-order mark
  if (auto s = r.read_header(); !s) return s.err();
  return r;
}

csv_reader::owned_fd& csv_reader::owned_fd::operator=(owned_fd&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
  }
  return *this;
}

csv_reader::owned_fd::~owned_fd() {
  if (fd_ >= 0) ::close(fd_);
}

bool csv_reader::refill() {
  if (stream_end_) return false;
  // A quarter of a megabyte a read: the block stays in the core's cache while its lines are cut
  // and parsed (a read() into one reused buffer costs half of a mapping's first touch of every
  // page on the virtual machines measured: docs/PERFORMANCE.md, issue 33).
  constexpr std::size_t block = std::size_t{1} << 18;
  const std::size_t left = buf_len_ - buf_pos_;
  if (left > 0 && buf_pos_ > 0) std::memmove(buf_.get(), buf_.get() + buf_pos_, left);
  buf_len_ = left;
  buf_pos_ = 0;
  if (buf_cap_ - buf_len_ < block) {
    const std::size_t cap = std::max(2 * buf_cap_, buf_len_ + block);
    auto grown = std::make_unique_for_overwrite<char[]>(cap);
    if (buf_len_ > 0) std::memcpy(grown.get(), buf_.get(), buf_len_);
    buf_ = std::move(grown);
    buf_cap_ = cap;
  }
  const int fd = fd_.get() < 0 ? STDIN_FILENO : fd_.get();  // no descriptor of its own: stdin
  while (true) {
    const ssize_t n = ::read(fd, buf_.get() + buf_len_, buf_cap_ - buf_len_);
    if (n > 0) {
      buf_len_ += static_cast<std::size_t>(n);
      return true;
    }
    if (n < 0 && errno == EINTR) continue;
    stream_end_ = true;  // end of input (or a read error: what came is what there is)
    return false;
  }
}

namespace {

// Where the next line of `left` bytes at `begin` ends: at its '\n' (`taken` includes it), or
// one byte past the longest allowed line (the caller reports that), or at the end of the input
// when `at_end`. Looks no further than that byte: a 2 GB file without a newline fails after
// 1 MiB, not after the whole mapping has been paged in. nullopt: no whole line yet.
struct line_cut {
  std::size_t len = 0, taken = 0;
  bool unterminated = false;
};
// The first '\n' in the `n` bytes at `begin`, or nullptr: eight bytes at a time with the exact
// byte test of for_each_field over a recording row's first 64 bytes (a 40-byte row costs five
// words instead of a call to memchr, which was 19 % of compensate's time: docs/PERFORMANCE.md,
// issue 33), memchr beyond (headers, comments, long rows).
const char* find_newline(const char* begin, std::size_t n) noexcept {
  constexpr std::uint64_t low7 = 0x7F7F7F7F7F7F7F7Full;
  constexpr std::uint64_t newlines = 0x0A0A0A0A0A0A0A0Aull;
  std::size_t i = 0;
  for (; i + 8 <= n && i < 64; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, begin + i, 8);
    const std::uint64_t x = w ^ newlines;
    const std::uint64_t t = ~(((x & low7) + low7) | x | low7);
    if (t != 0) return begin + i + static_cast<std::size_t>(std::countr_zero(t)) / 8;
  }
  return static_cast<const char*>(std::memchr(begin + i, '\n', n - i));
}

std::optional<line_cut> cut_line(const char* begin, std::size_t left, bool at_end) {
  const std::size_t window = std::min(left, max_line_bytes + 1);
  const auto* nl = find_newline(begin, window);
  if (nl != nullptr) {
    const auto len = static_cast<std::size_t>(nl - begin);
    return line_cut{len, len + 1, false};
  }
  if (window > max_line_bytes || (at_end && left > 0)) return line_cut{window, window, true};
  return std::nullopt;
}

}  // namespace

std::string_view csv_reader::take_line(const char* begin, std::size_t len, bool unterminated) {
  unterminated_ = unterminated;
  ++line_;
  if (len > 0 && begin[len - 1] == '\r') --len;
  return {begin, len};
}

std::optional<std::string_view> csv_reader::next_line() {
  if (has_replay_) {
    has_replay_ = false;
    ++line_;
    return std::string_view(replay_);
  }
  // Cut from what has come, reading more until a line is whole or the input ends.
  while (true) {
    const char* begin = buf_.get() + buf_pos_;
    if (const auto c = cut_line(begin, buf_len_ - buf_pos_, stream_end_)) {
      buf_pos_ += c->taken;
      pos_ += c->taken;
      return take_line(begin, c->len, c->unterminated);
    }
    if (!refill() && buf_pos_ == buf_len_) return std::nullopt;
  }
}

// The delimiter of a file from its first line: the most frequent of ';', tab and ',' (a
// decimal comma is no delimiter), else blanks between fields, else one column (any will do).
void csv_reader::detect_delimiter(std::string_view first_line) {
  char best = 0;
  std::ptrdiff_t most = 0;
  for (const char c : {';', '\t', ','}) {
    if (c == dialect_.decimal) continue;
    const auto n = std::count(first_line.begin(), first_line.end(), c);
    if (n > most) {
      most = n;
      best = c;
    }
  }
  if (best == 0) best = trim(first_line).find(' ') != std::string_view::npos ? ' ' : ',';
  dialect_.delimiter = best;
}

status csv_reader::read_header() {
  while (const auto l = next_line()) {
    if (l->size() > max_line_bytes)
      return input_error({path(), line_}, "line longer than 1 MiB (not a CSV recording?)");
    if (!l->empty() && l->front() == '#') {
      add_metadata(*l);
      continue;
    }
    if (is_blank(*l)) continue;
    if (dialect_.delimiter == 0) detect_delimiter(*l);
    header_line_ = line_;
    for_each_field(*l, dialect_.delimiter, [&](std::size_t begin, std::size_t end) {
      header_cols_.push_back(begin + 1);
      if (!dialect_.header) {
        header_.push_back(std::to_string(header_.size() + 1));
        return;
      }
      std::string_view name = trim(l->substr(begin, end - begin));
      // A quoted name ("gyro_x"), as spreadsheet programs write them.
      if (name.size() >= 2 && name.front() == '"' && name.back() == '"')
        name = name.substr(1, name.size() - 2);
      header_.emplace_back(name);
    });
    if (!dialect_.header) {
      // Every line is data: columns are numbered, and this line is handed out again as the
      // first row.
      replay_ = std::string(*l);
      has_replay_ = true;
      --line_;
    }
    slot_of_column_.assign(header_.size(), -1);
    return ok();
  }
  return input_error({path(), line_}, "no header line (file has only comments or blank lines)");
}

void csv_reader::add_metadata(std::string_view line) {
  const std::string_view body = trim(line.substr(1));
  const auto colon = body.find(':');
  if (colon == std::string_view::npos) return;
  const std::string_view value = trim(body.substr(colon + 1));
  metadata_.push_back({std::string(trim(body.substr(0, colon))), std::string(value), line_,
                       static_cast<std::size_t>(value.data() - line.data()) + 1});
}

result<std::optional<std::size_t>> csv_reader::find_column(std::string_view name) const {
  std::optional<std::size_t> found;
  for (std::size_t i = 0; i < header_.size(); ++i) {
    if (header_[i] != name) continue;
    if (found)
      return input_error({path(), header_line_, header_cols_[i]},
                         fmt::format("duplicated column '{}' (fields {} and {})", printable(name),
                                     *found + 1, i + 1));
    found = i;
  }
  // No such name: a column number (1-based), as for a file without a header.
  if (const auto number = text::to_unsigned(name);
      !found && number && *number >= 1 && *number <= header_.size())
    found = static_cast<std::size_t>(*number - 1);
  return found;
}

result<std::size_t> csv_reader::require_column(std::string_view name) const {
  auto f = find_column(name);
  if (!f) return f.err();
  if (!f.value())
    return input_error(
        {path(), header_line_, 1},
        fmt::format("missing required column '{}' (header: {}; fields split at {}{})",
                    printable(name), printable(fmt::format("{}", fmt::join(header_, ",")), 200),
                    delimiter_name(dialect_.delimiter),
                    dialect_.header ? "" : "; no header: columns are numbered from 1"));
  return *f.value();
}

void csv_reader::select(const std::vector<std::size_t>& columns) {
  selected_ = columns;
  std::fill(slot_of_column_.begin(), slot_of_column_.end(), -1);
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] != absent_column) slot_of_column_[columns[i]] = static_cast<int>(i);
  cells_.assign(columns.size(), {});
}

bool csv_reader::split(std::string_view line) {
  const std::size_t n_cols = header_.size();
  std::size_t col = 0;
  for_each_field(line, dialect_.delimiter, [&](std::size_t begin, std::size_t end) {
    if (col < n_cols) {
      const int slot = slot_of_column_[col];
      if (slot >= 0) cells_[static_cast<std::size_t>(slot)] = line.substr(begin, end - begin);
    }
    ++col;
  });
  if (col == n_cols) return true;
  error_ =
      input_error({path(), line_, std::min(line.size() + 1, max_line_bytes)},
                  fmt::format("row has {} field{}, header has {} (fields split at {})", col,
                              col == 1 ? "" : "s", n_cols, delimiter_name(dialect_.delimiter)));
  return false;
}

csv_reader::step csv_reader::next() {
  while (auto l = next_line()) {
    if (l->size() > max_line_bytes) {
      error_ = input_error({path(), line_}, "line longer than 1 MiB (missing newline?)");
      return step::failed;
    }
    if (!l->empty() && l->front() == '#') {
      if (!rows_seen_) add_metadata(*l);  // between the header and the first row: metadata too
      continue;
    }
    if (is_blank(*l)) continue;
    rows_seen_ = true;
    current_ = *l;
    return split(*l) ? step::row : step::failed;
  }
  return step::end;
}

namespace {

// The decimal digits at `p` (before `end`) appended to m, eight at a time where the line has
// eight more bytes (Lemire's SWAR digit test and combination, as in simdjson and fast_float:
// three multiplications for eight digits), one at a time otherwise; returns where they stop.
// Callers bound the count (at most 18 digits), so m does not overflow before it is checked.
[[gnu::always_inline]] inline const char* digits_of(const char* p, const char* end,
                                                    std::uint64_t& m) noexcept {
  static constexpr std::uint64_t pow10[] = {1,      10,      100,      1000,     10000,
                                            100000, 1000000, 10000000, 100000000};
  while (end - p >= 8) {
    std::uint64_t w;
    std::memcpy(&w, p, 8);
    // A byte is a digit when its high nibble is 3 and its low nibble at most 9 (+6 carries
    // into the high nibble only from 10 up; nothing carries across bytes).
    const std::uint64_t not_digit =
        ((w & 0xF0F0F0F0F0F0F0F0ull) ^ 0x3030303030303030ull) |
        (((w & 0x0F0F0F0F0F0F0F0Full) + 0x0606060606060606ull) & 0xF0F0F0F0F0F0F0F0ull);
    const auto n = not_digit == 0 ? 8u : static_cast<unsigned>(std::countr_zero(not_digit)) / 8;
    if (n == 0) return p;
    // The n leading digits moved to the word's high bytes, zeros before them: eight digits.
    std::uint64_t v = (w - 0x3030303030303030ull) << (8 * (8 - n));
    v = v * 10 + (v >> 8);
    v = (((v & 0x000000FF000000FFull) * (100 + (1000000ull << 32))) +
         (((v >> 16) & 0x000000FF000000FFull) * (1 + (10000ull << 32)))) >>
        32;
    m = m * pow10[n] + v;
    p += n;
    if (n < 8) return p;
  }
  for (; p != end; ++p) {
    const auto d = static_cast<unsigned>(*p) - unsigned{'0'};
    if (d >= 10) break;
    m = m * 10 + d;
  }
  return p;
}

}  // namespace

bool csv_reader::peek_plain(plain_row& row) {
  if (has_replay_ || dialect_.delimiter == ' ' || dialect_.decimal != '.' ||
      dialect_.missing_is_nan || selected_.size() > plain_row::max_cells ||
      slot_of_column_.size() != header_.size())
    return false;
  // A whole line in the buffer, not the input's last (the general path says if it is cut).
  if (buf_len_ - buf_pos_ < 256 && !stream_end_) refill();
  const char* const begin = buf_.get() + buf_pos_;
  const auto cut = cut_line(begin, buf_len_ - buf_pos_, false);
  if (!cut || cut->unterminated || cut->len == 0) return false;
  const char* p = begin;
  const char* end = begin + cut->len;
  if (end[-1] == '\r') --end;  // CRLF line ends
  const char delimiter = dialect_.delimiter;
  const std::size_t n_cols = header_.size();
  for (std::size_t col = 0; col < n_cols; ++col) {
    const int slot = slot_of_column_[col];
    if (slot < 0) {
      while (p != end && *p != delimiter) ++p;
    } else {
      // Digits, at most one point, an optional leading '-': the spellings parse_plain_decimal
      // takes, with its limits (at most 18 digits, so m < 10^18; m <= 2^53 exact).
      const bool negative = p != end && *p == '-';
      p += negative ? 1 : 0;
      std::uint64_t m = 0;
      int digits = 0, frac = -1;
      const char* const int_begin = p;
      p = digits_of(p, end, m);
      digits = static_cast<int>(p - int_begin);
      if (p != end && *p == '.') {
        const char* const frac_begin = ++p;
        p = digits_of(p, end, m);
        frac = static_cast<int>(p - frac_begin);
        digits += frac;
      }
      const auto k = static_cast<std::size_t>(slot);
      row.empty[k] = digits == 0;
      if (digits == 0 && (negative || frac >= 0)) return false;  // "-" or "." alone
      if (digits > 18 || m > (std::uint64_t{1} << 53)) return false;
      const double v =
          frac <= 0 ? static_cast<double>(m)
                    : static_cast<double>(m) / detail::exact_pow10[static_cast<std::size_t>(frac)];
      row.value[k] = negative ? -v : v;
    }
    // Each field ends at the delimiter, the last at the line's end: anything else (a blank, a
    // CR, an exponent, a field too many or too few) takes the general path.
    if (col + 1 < n_cols) {
      if (p == end || *p != delimiter) return false;
      ++p;
    } else if (p != end) {
      return false;
    }
  }
  row.taken = cut->taken;
  return true;
}

void csv_reader::commit_plain(const plain_row& row) noexcept {
  const char* begin = buf_.get() + buf_pos_;
  buf_pos_ += row.taken;
  pos_ += row.taken;
  rows_seen_ = true;
  unterminated_ = false;
  ++line_;
  current_ = std::string_view(begin, row.taken - 1);
}

std::string_view csv_reader::cell(std::size_t i) const noexcept {
  return trim(cells_[i]);
}

error csv_reader::error_at(std::size_t i, std::string_view what) const {
  const std::size_t col = static_cast<std::size_t>(cells_[i].data() - current_.data()) + 1;
  const std::string_view name =
      selected_[i] == absent_column ? std::string_view("?") : header_[selected_[i]];
  return input_error({path(), line_, col},
                     fmt::format("{} (column '{}')", what, printable(name, 60)));
}

error csv_reader::error_at_line(std::string_view what) const {
  return input_error({path(), line_}, what);
}

namespace {

// A missing sample as loggers write one: an empty field or nan in any case, with a sign (C's
// printf writes a NaN with its sign bit as -nan).
bool is_missing(std::string_view s) {
  if (s.empty()) return true;
  if (s.size() > 1 && (s.front() == '-' || s.front() == '+')) s.remove_prefix(1);
  if (s.size() != 3) return false;
  const auto lower = [](char c) { return static_cast<char>(c | 0x20); };
  return lower(s[0]) == 'n' && lower(s[1]) == 'a' && lower(s[2]) == 'n';
}

}  // namespace

bool csv_reader::parse_slow(std::size_t i, double& out) {
  std::string_view s = cell(i);
  if (dialect_.missing_is_nan && is_missing(s)) {
    out = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  char buf[64];
  if (dialect_.decimal == ',') {
    // A decimal comma: the number as from_chars reads it. A '.' as well is a thousands mark or
    // another dialect, which gyroflip does not guess at.
    if (s.find('.') != std::string_view::npos) {
      error_ = error_at(
          i, fmt::format("'{}' has a '.' while the decimal mark is ','", printable(s, 40)));
      return false;
    }
    if (s.size() < sizeof buf) {
      std::replace_copy(s.begin(), s.end(), buf, ',', '.');
      s = std::string_view(buf, s.size());
    }
  }
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;  // from_chars rejects a leading '+'; people write it
  if (detail::parse_plain_decimal(b, e, out)) return true;
  const auto [p, ec] = std::from_chars(b, e, out);
  if (ec == std::errc{} && p == e && std::abs(out) <= max_magnitude) return true;
  if (s.empty()) {
    error_ = error_at(i, "empty field, expected a number");
  } else if (ec == std::errc{} && p == e && std::isfinite(out)) {
    error_ = error_at(i, fmt::format("'{}' is beyond +-{:g}, the largest magnitude gyroflip reads "
                                     "(not a measurement; results would overflow)",
                                     printable(s, 40), max_magnitude));
  } else if (ec == std::errc{} && p == e) {
    error_ = error_at(i, fmt::format("'{}' is not a finite number", printable(s, 40)));
  } else if (ec == std::errc::result_out_of_range) {
    error_ = error_at(i, fmt::format("'{}' is out of the range of a double", printable(s, 40)));
  } else {
    error_ = error_at(i, fmt::format("'{}' is not a number", printable(s, 40)));
  }
  return false;
}

result<std::vector<std::vector<double>>> read_numeric_columns(
    const std::string& path, const std::vector<std::string>& names) {
  auto r = csv_reader::open(path);
  if (!r) return r.err();
  std::vector<std::size_t> idx;
  for (const auto& n : names) {
    auto c = r->require_column(n);
    if (!c) return c.err();
    idx.push_back(*c);
  }
  r->select(idx);
  std::vector<std::vector<double>> cols(names.size());
  // Reserve from a size estimate so that large files do not reallocate repeatedly.
  const std::size_t guess = static_cast<std::size_t>(
      r->bytes_total() / (8 * std::max<std::size_t>(1, r->header().size())));
  for (auto& c : cols) c.reserve(guess);
  while (true) {
    const auto s = r->next();
    if (s == csv_reader::step::end) break;
    if (s == csv_reader::step::failed) return r->last_error();
    for (std::size_t i = 0; i < cols.size(); ++i) {
      double v = 0.0;
      if (!r->parse(i, v)) return r->last_error();
      cols[i].push_back(v);
    }
  }
  return cols;
}

result<time_table> read_time_table(const std::string& path, std::string_view column) {
  auto r = csv_reader::open(path);
  if (!r) return r.err();
  auto t = r->require_column("time_s");
  if (!t) return t.err();
  auto v = r->require_column(column);
  if (!v) return v.err();
  r->select({*t, *v});
  time_table out;
  while (true) {
    const auto s = r->next();
    if (s == csv_reader::step::end) break;
    if (s == csv_reader::step::failed) return r->last_error();
    double ts = 0.0;
    double x = 0.0;
    if (!r->parse(0, ts) || !r->parse(1, x)) return r->last_error();
    if (!out.time_s.empty() && !(ts > out.time_s.back()))
      return r->error_at(
          0, fmt::format("time_s {} does not increase (previous {})", ts, out.time_s.back()));
    out.time_s.push_back(ts);
    out.value.push_back(x);
  }
  if (out.time_s.empty()) return input_error({path}, "no data rows after the header");
  return out;
}

}  // namespace gyroflip::io
