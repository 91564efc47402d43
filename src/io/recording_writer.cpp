/// \file
/// \brief Recording writer (see recording_writer.hpp).
#include "gyroflip/io/recording_writer.hpp"

#include <cmath>
#include <iterator>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip::io {
namespace {

// `{}` is fmt's shortest round-trip form; NaN marks an empty field.
void field(std::string& out, double v) {
  if (!std::isnan(v)) fmt::format_to(std::back_inserter(out), "{}", v);
}

}  // namespace

void append_metadata(std::string& out, std::span<const csv_metadata> metadata) {
  for (const auto& m : metadata)
    fmt::format_to(std::back_inserter(out), "# {}: {}\n", printable(m.key, 200),
                   printable(m.value, 4096));
}

void append_recording_header(std::string& out, std::span<const csv_metadata> metadata) {
  append_metadata(out, metadata);
  out += "time_s,angle_deg,rate_dps,temp_c,n_avg\n";
}

void append_recording_row(std::string& out, const method::row& r, const position_table& table) {
  fmt::format_to(std::back_inserter(out), "{},", r.time_s);
  field(out, table.holds(r.position) ? table.angle_deg(r.position) : method::no_value);
  fmt::format_to(std::back_inserter(out), ",{},", r.rate_dps);
  fmt::format_to(std::back_inserter(out), "{},{}\n", r.temp_c, r.n_avg);
}

}  // namespace gyroflip::io
