/// \file
/// \brief Fast, strict reader of numeric CSV files (docs/FORMATS.md, "CSV rules").
///
/// The file is read a block at a time (docs/PERFORMANCE.md, issue 33: faster than a mapping on a
/// virtual machine, and a file cut short while read is no SIGBUS) and numbers are parsed with
/// `std::from_chars`. Rules: UTF-8,
/// comma-separated, a UTF-8 BOM and CRLF line ends accepted; lines starting with `#` are
/// comments (`# key: value` lines before the first data row are kept as metadata); blank lines are
/// skipped; the first other line is the header; every data row has exactly as many fields
/// as the header. Every problem is reported as `FILE:LINE:COL: what` (1-based).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/metadata.hpp"
#include "gyroflip/core/result.hpp"

namespace gyroflip::io {

namespace detail {

/// Exact fast path for plain decimals such as "-1234.5670" (Clinger 1990): when the digits
/// form an integer m <= 2^53 and there are k <= 22 fraction digits, m and 10^k are exact
/// doubles and the one division m / 10^k is correctly rounded - the value `from_chars` gives.
/// Returns false for anything else (blanks, '+', exponents, long mantissas, nan, inf).
/// The powers of ten that are exact doubles (10^0 .. 10^22), the divisors of the exact fast path.
inline constexpr double exact_pow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                         1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                         1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
inline bool parse_plain_decimal(const char* b, const char* e, double& out) noexcept {
  const bool negative = b != e && *b == '-';
  b += negative ? 1 : 0;
  // At most 19 characters: 18 digits and a point, so m < 10^18 cannot overflow.
  if (b == e || e - b > 19) return false;
  std::uint64_t m = 0;
  const char* dot = nullptr;
  for (const char* p = b; p != e; ++p) {
    const auto d = static_cast<unsigned>(*p) - unsigned{'0'};
    if (d < 10) {
      m = m * 10 + d;
    } else if (*p == '.' && dot == nullptr) {
      dot = p;
    } else {
      return false;
    }
  }
  if (e - b == 1 && dot != nullptr) return false;  // "." alone is not a number
  if (m > (std::uint64_t{1} << 53)) return false;
  const auto frac = dot != nullptr ? static_cast<std::size_t>(e - dot - 1) : 0;
  // An integer (n_avg) needs no division (x / 1 is x: the same double, without the divide's
  // latency in the row's chain).
  const double v = frac == 0 ? static_cast<double>(m) : static_cast<double>(m) / exact_pow10[frac];
  out = negative ? -v : v;
  return true;
}

}  // namespace detail

/// One `# key: value` comment line found before the header.
using csv_metadata = metadata_entry;

/// How a file's fields are written (docs/FORMATS.md, "CSV rules"): what loggers write besides
/// gyroflip's own comma-separated files with a header.
struct csv_dialect {
  /// Field separator: ',' ';' '\t', ' ' (any run of blanks), or 0 to detect it from the first
  /// line: the most frequent of ';', '\t' and ',' (',' not when it is the decimal mark), else
  /// blanks between fields, else one column.
  char delimiter = 0;
  char decimal = '.';  ///< '.' or ',' (then the delimiter cannot be ',')
  bool header = true;  ///< false: every line is data; columns are named 1, 2, ...
  /// An empty field or `nan` in any case, signed or not (`-nan`, as C's printf writes a NaN with
  /// its sign bit), is a missing sample, read as NaN (GRADEV's gaps); otherwise an error.
  bool missing_is_nan = false;
};

/// The delimiter's name for messages ("','", "';'", "tab", "blanks").
[[nodiscard]] std::string delimiter_name(char delimiter);

class csv_reader {
 public:
  /// Opens `path` and reads comments and header; `-` reads standard input as it comes (a pipe from
  /// a logger: only the lines not yet consumed are held). Errors: missing file, directory, empty
  /// file, binary data, no header, a dialect whose decimal mark is its delimiter.
  [[nodiscard]] static result<csv_reader> open(const std::string& path,
                                               const csv_dialect& dialect = {});
  /// The dialect in use (the delimiter as detected).
  [[nodiscard]] const csv_dialect& dialect() const noexcept { return dialect_; }

  /// The file's path, or `<stdin>`.
  [[nodiscard]] const std::string& path() const noexcept { return path_; }
  [[nodiscard]] const std::vector<std::string>& header() const noexcept { return header_; }
  [[nodiscard]] const std::vector<csv_metadata>& metadata() const noexcept { return metadata_; }

  /// Index of column `name`, or of the 1-based column number `name` when no column has that
  /// name (for files without a header); nullopt if absent. Error if the name appears more than
  /// once.
  [[nodiscard]] result<std::optional<std::size_t>> find_column(std::string_view name) const;
  /// Index of column `name`; error (naming the header line) if absent or duplicated.
  [[nodiscard]] result<std::size_t> require_column(std::string_view name) const;

  /// Marks a slot in `select()` whose column the file does not have (its cell stays empty).
  static constexpr std::size_t absent_column = static_cast<std::size_t>(-1);

  /// Chooses the columns that `cell(i)` returns after `next()`: `cell(i)` is column
  /// `columns[i]` (always empty for `absent_column`). Must be called before the first `next()`.
  void select(const std::vector<std::size_t>& columns);

  enum class step { row, end, failed };
  /// Advances to the next data row. On `failed`, `last_error()` says why (bad field count,
  /// over-long line). Comment and blank lines are skipped.
  [[nodiscard]] step next();
  [[nodiscard]] const error& last_error() const noexcept { return error_; }

  /// Text of selected cell `i` in the current row, surrounding blanks removed.
  [[nodiscard]] std::string_view cell(std::size_t i) const noexcept;
  /// Largest magnitude a number may have (docs/FORMATS.md): within it the method's and the
  /// analysis' sums and squares cannot overflow.
  static constexpr double max_magnitude = max_input_magnitude;
  /// Parses selected cell `i` as a finite double of magnitude <= max_magnitude. On failure returns
  /// false and sets `last_error()` to `FILE:LINE:COL: ...` naming the column. Inline fast path for
  /// plain decimals without blanks; everything else (and every error) goes through parse_slow.
  [[nodiscard]] bool parse(std::size_t i, double& out) {
    const std::string_view s = cells_[i];
    return (dialect_.decimal == '.' &&
            detail::parse_plain_decimal(s.data(), s.data() + s.size(), out)) ||
           parse_slow(i, out);
  }
  /// A data row read by the fast path: each selected cell's value, or `empty` for an empty field.
  struct plain_row {
    static constexpr std::size_t max_cells = 8;
    double value[max_cells] = {};
    bool empty[max_cells] = {};
    std::size_t taken = 0;  // bytes of its line, newline included
  };
  /// The fast path of a recording's rows (docs/PERFORMANCE.md, issue 33): cuts the next line and
  /// parses every selected field as a plain decimal (as parse()'s fast path does) in one pass,
  /// consuming nothing. False when the line needs next(): a comment, a blank line, blanks or any
  /// other spelling in a field, a wrong field count, a line not yet whole or ending the input, a
  /// dialect other than the default. commit_plain() then consumes the row.
  [[nodiscard]] bool peek_plain(plain_row& row);
  void commit_plain(const plain_row& row) noexcept;
  /// Builds an error located at selected cell `i` of the current row.
  [[nodiscard]] error error_at(std::size_t i, std::string_view what) const;
  /// Builds an error located at the current line (no column).
  [[nodiscard]] error error_at_line(std::string_view what) const;

  /// True when the current row's line ends the file without a newline: the file may have been
  /// cut inside this row (a writer killed mid-line, a disk that filled up).
  [[nodiscard]] bool unterminated() const noexcept { return unterminated_; }
  /// 1-based line number of the current row (or of the header before the first row).
  [[nodiscard]] std::size_t line() const noexcept { return line_; }
  /// Bytes consumed and total (0 for standard input: not known), for progress display.
  [[nodiscard]] std::uint64_t bytes_done() const noexcept { return pos_; }
  [[nodiscard]] std::uint64_t bytes_total() const noexcept { return size_bytes_; }

 private:
  // An open descriptor, closed with its owner (a reader is moved out of open()).
  class owned_fd {
   public:
    owned_fd() = default;
    explicit owned_fd(int fd) noexcept : fd_(fd) {}
    owned_fd(owned_fd&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
    owned_fd& operator=(owned_fd&& o) noexcept;
    owned_fd(const owned_fd&) = delete;
    owned_fd& operator=(const owned_fd&) = delete;
    ~owned_fd();
    [[nodiscard]] int get() const noexcept { return fd_; }

   private:
    int fd_ = -1;
  };
  csv_reader(owned_fd fd, std::string path, std::uint64_t size_bytes)
      : path_(std::move(path)), fd_(std::move(fd)), size_bytes_(size_bytes) {}
  status read_header();
  // Returns the next line (without end-of-line characters) or nullopt at end of file. The view
  // is valid until the next call.
  std::optional<std::string_view> next_line();
  // Counts line `begin`..`len` (a CR before its end dropped) and returns it.
  std::string_view take_line(const char* begin, std::size_t len, bool unterminated);
  // Reads more of the input into buf_ (moving what is not consumed to its front); false at its
  // end.
  bool refill();
  void add_metadata(std::string_view comment_line);
  bool split(std::string_view line);
  void detect_delimiter(std::string_view first_line);
  [[nodiscard]] bool parse_slow(std::size_t i, double& out);

  std::string path_;
  csv_dialect dialect_;
  std::size_t pos_ = 0;  // bytes consumed
  // The input is read a block at a time: only the lines not yet consumed are held.
  owned_fd fd_;
  std::uint64_t size_bytes_ = 0;  // 0: standard input (not known)
  std::unique_ptr<char[]> buf_;
  std::size_t buf_cap_ = 0, buf_len_ = 0, buf_pos_ = 0;
  bool stream_end_ = false;
  std::string replay_;  // a line to hand out again (a file without a header: its first row)
  bool has_replay_ = false;
  std::size_t line_ = 0;
  std::size_t header_line_ = 0;
  bool unterminated_ = false;
  bool rows_seen_ = false;
  std::vector<std::string> header_;
  std::vector<std::size_t> header_cols_;  // 1-based column where each header field starts
  std::vector<csv_metadata> metadata_;
  std::vector<std::size_t> selected_;
  std::vector<int> slot_of_column_;  // column index -> selected slot, -1 when not selected
  std::vector<std::string_view> cells_;
  std::string_view current_;
  error error_{errc::bad_input, {}};
};

/// Two columns of a CSV table: `time_s` and `column`, time strictly increasing (`FILE:LINE:COL`
/// naming the row that is not). For `simulate --temp-profile FILE.csv`.
struct time_table {
  std::vector<double> time_s;
  std::vector<double> value;
};
[[nodiscard]] result<time_table> read_time_table(const std::string& path, std::string_view column);

/// Reads whole columns by name as doubles (every data row). For tools that need the full
/// series in memory (`gyroflip adev` on CSV input). Errors as csv_reader.
[[nodiscard]] result<std::vector<std::vector<double>>> read_numeric_columns(
    const std::string& path, const std::vector<std::string>& names);

}  // namespace gyroflip::io
