/// \file
/// \brief Recording reader (see recording.hpp).
#include "gyroflip/io/recording.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <system_error>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::io {
namespace {

// Slots of the selected columns in csv_reader.
enum slot : std::size_t { s_time, s_angle, s_rate, s_temp, s_navg };

status check_tolerance(double angle_tolerance_deg) {
  constexpr double most = recording_reader::max_angle_tolerance_deg;
  if (angle_tolerance_deg >= 0.0 && angle_tolerance_deg <= most) return ok();
  return parameter_error("angle_tolerance_deg",
                         fmt::format("the angle tolerance must be 0 to {:g} deg", most));
}

// A recording's `# positions_deg:` line: absent, `auto`, or the table it names; errors name its
// line and the column of the bad angle.
struct table_line {
  const csv_metadata* line = nullptr;  // null: no such line
  bool automatic = false;              // `auto`: the rows' distinct angles
  position_table table;
};
result<table_line> table_of_line(const std::string& path, std::span<const csv_metadata> metadata) {
  table_line out;
  for (const auto& m : metadata)
    if (m.key == "positions_deg") {
      if (out.line != nullptr)
        return input_error(
            {path, m.line, 1},
            fmt::format("a second # positions_deg line (the first is line {})", out.line->line));
      out.line = &m;
    }
  if (out.line == nullptr) return out;
  const csv_metadata& line = *out.line;
  const std::string_view v = line.value;
  if (v == "auto") {
    out.automatic = true;
    return out;
  }
  std::vector<double> angles;
  for (std::size_t at = 0; at <= v.size();) {
    const std::size_t comma = std::min(v.find(',', at), v.size());
    std::string_view item = v.substr(at, comma - at);
    std::size_t lead = 0;
    while (lead < item.size() && (item[lead] == ' ' || item[lead] == '\t')) ++lead;
    item.remove_prefix(lead);
    while (!item.empty() && (item.back() == ' ' || item.back() == '\t')) item.remove_suffix(1);
    const source_location where{path, line.line, line.column + at + lead};
    double a = 0.0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), a);
    if (item.empty() || ec != std::errc{} || end != item.data() + item.size())
      return input_error(where, fmt::format("positions_deg: '{}' is not an angle in degrees "
                                            "(expected A,B,... or auto: the table's angles)",
                                            printable(item, 40)));
    if (!(a >= 0.0 && a < 360.0))
      return input_error(where,
                         fmt::format("positions_deg: {} is not an angle in [0, 360) deg", item));
    for (std::size_t j = 0; j < angles.size(); ++j)
      if (angles[j] == a)
        return input_error(
            where, fmt::format("positions_deg: {} deg is position {} already: a table's angles "
                               "differ",
                               item, j));
    if (angles.size() == position_table::max_positions)
      return input_error(where, fmt::format("positions_deg: more than {} positions",
                                            position_table::max_positions));
    angles.push_back(a);
    at = comma + 1;
  }
  auto t = position_table::of_angles(angles);
  if (!t) return input_error({path, line.line, line.column}, t.err().message);
  out.table = std::move(*t);
  return out;
}

// Adds angle `a` (any finite value: 360 is 0, -90 is 270) to `seen`, the distinct angles so far;
// error text when it would be a ninth.
std::string add_angle(std::vector<double>& seen, double a) {
  a = std::fmod(std::fmod(a, 360.0) + 360.0, 360.0);
  if (std::find(seen.begin(), seen.end(), a) != seen.end()) return {};
  if (seen.size() == position_table::max_positions)
    return fmt::format(
        "angle {} deg would be a table's {}th position (# positions_deg: auto; a "
        "table holds at most {})",
        a, seen.size() + 1, position_table::max_positions);
  seen.push_back(a);
  return {};
}

// A table of distinct angles, ascending.
position_table table_of_seen(std::vector<double> seen) {
  std::sort(seen.begin(), seen.end());
  auto t = position_table::of_angles(seen);
  return t ? std::move(*t) : position_table{};
}

// The distinct angles of a file's rows (a first pass over its angle column). Cells that are not
// numbers are passed over: the reading pass names them.
result<position_table> table_of_file(const std::string& path, const csv_dialect& dialect) {
  auto c = csv_reader::open(path, dialect);
  if (!c) return c.err();
  auto col = c->require_column("angle_deg");
  if (!col) return col.err();
  c->select({*col});
  std::vector<double> seen;
  for (;;) {
    const auto st = c->next();
    if (st != csv_reader::step::row) break;  // the end, or an error the reading pass reports
    if (c->cell(0).empty()) continue;
    double a = 0.0;
    if (!c->parse(0, a)) continue;
    if (auto what = add_angle(seen, a); !what.empty()) return c->error_at(0, what);
  }
  return table_of_seen(std::move(seen));
}

}  // namespace

result<recording_reader> recording_reader::open(const std::string& path,
                                                double angle_tolerance_deg) {
  if (auto s = check_tolerance(angle_tolerance_deg); !s) return s.err();
  auto c = csv_reader::open(path);
  if (!c) return c.err();
  recording_reader r(std::move(*c));
  r.angle_tolerance_deg_ = angle_tolerance_deg;
  std::vector<std::size_t> cols;
  for (const char* name : {"time_s", "angle_deg", "rate_dps"}) {
    auto i = r.csv_.require_column(name);
    if (!i) return i.err();
    cols.push_back(*i);
  }
  auto temp = r.csv_.find_column("temp_c");
  if (!temp) return temp.err();
  auto navg = r.csv_.find_column("n_avg");
  if (!navg) return navg.err();
  r.has_temp_ = temp->has_value();
  r.has_n_avg_ = navg->has_value();
  cols.push_back(r.has_temp_ ? **temp : csv_reader::absent_column);
  cols.push_back(r.has_n_avg_ ? **navg : csv_reader::absent_column);
  r.csv_.select(cols);
  auto table = table_of_line(r.csv_.path(), r.csv_.metadata());
  if (!table) return table.err();
  if (table->automatic) {
    const source_location where{r.csv_.path(), table->line->line, table->line->column};
    if (path == "-")
      return input_error(where,
                         "positions_deg: auto reads the file twice; standard input "
                         "cannot be: give the table's angles");
    if (angle_tolerance_deg != 0.0)
      return input_error(where,
                         "positions_deg: auto takes the angles as written; with an "
                         "angle tolerance give the table's angles");
    auto seen = table_of_file(path, r.csv_.dialect());
    if (!seen) return seen.err();
    r.table_ = std::move(*seen);
    r.origin_ = table_origin::rows;
  } else if (table->line != nullptr) {
    r.table_ = std::move(table->table);
    r.origin_ = table_origin::line;
  } else {
    r.table_ = position_table::pair_0_180();
    r.origin_ = table_origin::pair_0_180;
  }
  // The common spellings `0` and `180` skip the number parser (the hot path of old recordings).
  r.at_0_ = r.table_.index_of(0.0, angle_tolerance_deg).value_or(table_moving);
  r.at_180_ = r.table_.index_of(180.0, angle_tolerance_deg).value_or(table_moving);
  return r;
}

csv_reader::step recording_reader::fail(const error& e) {
  error_ = e;
  return csv_reader::step::failed;
}

namespace {

std::string angle_message(std::string_view angle, double tol, const position_table& table,
                          table_origin origin) {
  const char* from = origin == table_origin::line ? "the positions of its # positions_deg line"
                     : origin == table_origin::rows
                         ? "the positions of its table"
                         : "the paper's pair; a # positions_deg line names any other table";
  return fmt::format(
      "angle {} deg is not supported: only {} ({}){}; leave it empty while the table turns", angle,
      table.describe(), from,
      tol > 0.0 ? fmt::format(", within {:g} deg", tol)
                : std::string(" (an encoder angle: give a tolerance)"));
}

// A row's temperature and n_avg, one rule for the CSV reader and for columns in memory: what is
// wrong (empty when nothing is). Written so that NaN fails.
std::string temperature_problem(double t) {
  constexpr double lo = recording_reader::min_temp_c, hi = recording_reader::max_temp_c;
  if (t >= lo && t <= hi) return {};
  return fmt::format("temperature {:g} degC is outside [{:g}, {:g}]", t, lo, hi);
}

std::string n_avg_problem(double n, std::string_view as_written) {
  if (n >= 1.0 && n == std::floor(n) && n <= std::numeric_limits<std::uint32_t>::max()) return {};
  return fmt::format("n_avg {} is not a whole number >= 1", as_written);
}

}  // namespace

bool recording_reader::next_plain(method::row& out) {
  csv_reader::plain_row r;
  if (!csv_.peek_plain(r)) return false;
  // The general path's checks on the numbers; whatever fails them takes that path, which says why.
  const double t = r.value[s_time];
  if (r.empty[s_time] || r.empty[s_rate] || t < last_time_s_) return false;
  int position = table_moving;  // an empty angle: the table turning
  if (!r.empty[s_angle]) {
    const double a = r.value[s_angle];
    if (a == 0.0 && at_0_ != table_moving) {
      position = at_0_;
    } else if (a == 180.0 && at_180_ != table_moving) {
      position = at_180_;
    } else {
      const auto pos = table_.index_of(a, angle_tolerance_deg_);
      if (!pos) return false;
      position = *pos;
    }
  }
  double temp_c = method::no_value;
  if (has_temp_) {
    temp_c = r.value[s_temp];
    if (r.empty[s_temp] || !(temp_c >= min_temp_c && temp_c <= max_temp_c)) return false;
  }
  std::uint32_t n_avg = 1;
  if (has_n_avg_) {
    const double n = r.value[s_navg];
    if (r.empty[s_navg] ||
        !(n >= 1.0 && n == std::floor(n) && n <= std::numeric_limits<std::uint32_t>::max()))
      return false;
    n_avg = static_cast<std::uint32_t>(n);
  }
  csv_.commit_plain(r);
  out.time_s = t;
  out.position = position;
  out.rate_dps = r.value[s_rate];
  out.temp_c = temp_c;
  out.n_avg = n_avg;
  last_time_s_ = t;
  last_time_line_ = csv_.line();
  return true;
}

csv_reader::step recording_reader::next(method::row& out) {
  if (next_plain(out)) return csv_reader::step::row;
  const auto s = csv_.next();
  if (s != csv_reader::step::row) {
    if (s == csv_reader::step::failed) error_ = csv_.last_error();
    return s;
  }
  if (!csv_.parse(s_time, out.time_s)) return fail(csv_.last_error());
  if (out.time_s < last_time_s_)
    return fail(csv_.error_at(s_time, fmt::format("time goes backwards: {} after {} on line {}",
                                                  out.time_s, last_time_s_, last_time_line_)));
  last_time_s_ = out.time_s;
  last_time_line_ = csv_.line();

  const std::string_view a = csv_.cell(s_angle);
  if (a.empty()) {
    out.position = table_moving;                   // table turning
  } else if (a == "0" && at_0_ != table_moving) {  // fast path for the common spellings
    out.position = at_0_;
  } else if (a == "180" && at_180_ != table_moving) {
    out.position = at_180_;
  } else {
    double angle = 0.0;
    if (!csv_.parse(s_angle, angle)) return fail(csv_.last_error());
    const auto pos = table_.index_of(angle, angle_tolerance_deg_);
    if (!pos)
      return fail(csv_.error_at(s_angle, angle_message(a, angle_tolerance_deg_, table_, origin_)));
    out.position = *pos;
  }
  if (!csv_.parse(s_rate, out.rate_dps)) return fail(csv_.last_error());
  if (has_temp_) {
    if (!csv_.parse(s_temp, out.temp_c)) return fail(csv_.last_error());
    if (auto what = temperature_problem(out.temp_c); !what.empty())
      return fail(csv_.error_at(s_temp, what));
  } else {
    out.temp_c = method::no_value;
  }
  out.n_avg = 1;
  if (has_n_avg_) {
    double n = 0.0;
    if (!csv_.parse(s_navg, n)) return fail(csv_.last_error());
    if (auto what = n_avg_problem(n, csv_.cell(s_navg)); !what.empty())
      return fail(csv_.error_at(s_navg, what));
    out.n_avg = static_cast<std::uint32_t>(n);
  }
  // The last line has no newline although earlier lines do: the writer may have stopped inside
  // this row (`...,20.03,2` where n_avg was 256). A cut n_avg would weigh the dwell wrongly and
  // cannot be told from a true one, so that row is refused; other columns get a warning.
  if (csv_.unterminated()) {
    if (has_n_avg_)
      return fail(
          csv_.error_at(s_navg,
                        "the file ends inside this row (no newline after it): it may have been cut "
                        "short, so its n_avg cannot be trusted; complete or delete the line"));
    warnings_.push_back(
        input_error({path(), csv_.line()},
                    "the file ends without a newline after this row: it may have been cut short")
            .message);
  }
  return csv_reader::step::row;
}

result<std::size_t> recording_reader::read(std::span<method::row> out) {
  std::size_t n = 0;
  while (n < out.size()) {
    const auto s = next(out[n]);
    if (s == csv_reader::step::end) break;
    if (s == csv_reader::step::failed) return error_;
    ++n;
  }
  return n;
}

result<table_rows> rows_of_columns(const recording_columns& c, double angle_tolerance_deg) {
  const std::size_t n = c.time_s.size();
  const auto wrong_length = [&](std::string_view name, std::size_t k) {
    return usage_error(fmt::format("{} has {} values but time_s has {}: one per row", name, k, n));
  };
  if (c.angle_deg.size() != n) return wrong_length("angle_deg", c.angle_deg.size());
  if (c.rate_dps.size() != n) return wrong_length("rate_dps", c.rate_dps.size());
  if (!c.temp_c.empty() && c.temp_c.size() != n) return wrong_length("temp_c", c.temp_c.size());
  if (!c.n_avg.empty() && c.n_avg.size() != n) return wrong_length("n_avg", c.n_avg.size());
  if (auto s = check_tolerance(angle_tolerance_deg); !s) return s.err();
  const auto bad = [](std::string_view name, std::size_t k, std::string_view what) {
    return usage_error(fmt::format("{}[{}]: {}", name, k, what));
  };
  // The table: as given, else the paper's pair (as a CSV without its table line).
  table_rows out;
  table_origin origin = table_origin::line;
  if (!c.positions_deg.empty()) {
    auto t = position_table::of_angles(c.positions_deg);
    if (!t) return usage_error(fmt::format("positions_deg: {}", t.err().message));
    out.positions = std::move(*t);
  } else {
    out.positions = position_table::pair_0_180();
    origin = table_origin::pair_0_180;
  }
  auto& rows = out.rows;
  rows.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    auto& r = rows[k];
    r.time_s = c.time_s[k];
    // The bound every number read from a file obeys (csv_reader::parse), for columns in memory.
    if (!(std::abs(r.time_s) <= max_input_magnitude))
      return bad("time_s", k, "not a finite number within +-1e100");
    if (k > 0 && r.time_s < rows[k - 1].time_s)
      return bad("time_s", k,
                 fmt::format("time goes backwards: {} after {}", r.time_s, rows[k - 1].time_s));
    if (std::isnan(c.angle_deg[k])) {
      r.position = table_moving;  // table turning
    } else {
      const auto pos = out.positions.index_of(c.angle_deg[k], angle_tolerance_deg);
      if (!pos)
        return bad("angle_deg", k,
                   angle_message(fmt::format("{}", c.angle_deg[k]), angle_tolerance_deg,
                                 out.positions, origin));
      r.position = *pos;
    }
    r.rate_dps = c.rate_dps[k];
    if (!(std::abs(r.rate_dps) <= max_input_magnitude))
      return bad("rate_dps", k, "not a finite number within +-1e100");
    if (!c.temp_c.empty()) {
      r.temp_c = c.temp_c[k];
      if (auto what = temperature_problem(r.temp_c); !what.empty()) return bad("temp_c", k, what);
    }
    if (!c.n_avg.empty()) {
      const double v = c.n_avg[k];
      if (auto what = n_avg_problem(v, fmt::format("{}", v)); !what.empty())
        return bad("n_avg", k, what);
      r.n_avg = static_cast<std::uint32_t>(v);
    }
  }
  return out;
}

}  // namespace gyroflip::io
