/// \file
/// \brief Recording reader (see recording.hpp).
#include "gyroflip/io/recording.hpp"

#include <cmath>
#include <limits>

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
  return r;
}

csv_reader::step recording_reader::fail(const error& e) {
  error_ = e;
  return csv_reader::step::failed;
}

std::optional<double> position_of_angle(double angle_deg, double tol) noexcept {
  // An encoder's reading: within the tolerance of 0 (or 360, or -0.x) or of 180.
  const double turned = std::fmod(std::fmod(angle_deg, 360.0) + 360.0, 360.0);
  if (std::abs(turned) <= tol || std::abs(turned - 360.0) <= tol) return 0.0;
  if (std::abs(turned - 180.0) <= tol) return 180.0;
  return std::nullopt;
}

namespace {

std::string angle_message(std::string_view angle, double tol) {
  return fmt::format(
      "angle {} deg is not supported: only 0 and 180 (two-position flipping){}; leave it empty "
      "while the table turns",
      angle,
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

csv_reader::step recording_reader::next(method::row& out) {
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
    out.angle_deg = method::no_value;  // table turning
  } else if (a == "0") {               // fast path for the common spellings
    out.angle_deg = 0.0;
  } else if (a == "180") {
    out.angle_deg = 180.0;
  } else {
    if (!csv_.parse(s_angle, out.angle_deg)) return fail(csv_.last_error());
    const auto pos = position_of_angle(out.angle_deg, angle_tolerance_deg_);
    if (!pos) return fail(csv_.error_at(s_angle, angle_message(a, angle_tolerance_deg_)));
    out.angle_deg = *pos;
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

result<std::vector<method::row>> rows_of_columns(const recording_columns& c,
                                                 double angle_tolerance_deg) {
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
  std::vector<method::row> rows(n);
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
      r.angle_deg = method::no_value;  // table turning
    } else {
      const auto pos = position_of_angle(c.angle_deg[k], angle_tolerance_deg);
      if (!pos)
        return bad("angle_deg", k,
                   angle_message(fmt::format("{}", c.angle_deg[k]), angle_tolerance_deg));
      r.angle_deg = *pos;
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
  return rows;
}

}  // namespace gyroflip::io
