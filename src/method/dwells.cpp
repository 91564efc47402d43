/// \file
/// \brief Rows -> dwells (see dwells.hpp).
#include "gyroflip/method/dwells.hpp"

#include <cmath>

namespace gyroflip::method {

dwell dwell_builder::close() const {
  dwell d;
  d.position = position_;
  d.time_s = sum_t_ / sum_w_;
  d.rate_dps = sum_y_ / sum_w_;
  d.temp_c = sum_w_temp_ > 0.0 ? sum_temp_ / sum_w_temp_ : no_value;
  d.weight = static_cast<std::uint64_t>(sum_w_);
  return d;
}

std::optional<dwell> dwell_builder::start(const row& r, int position) {
  std::optional<dwell> done;
  if (position_ != table_moving) done = close();
  sum_w_ = sum_t_ = sum_y_ = sum_temp_ = sum_w_temp_ = 0.0;
  position_ = position;
  add(r);
  return done;
}

std::optional<dwell> dwell_builder::flush() {
  if (position_ == table_moving) return std::nullopt;
  const dwell d = close();
  *this = dwell_builder{};
  return d;
}

std::vector<dwell> extract_dwells(std::span<const row> rows) {
  std::vector<dwell> out;
  dwell_builder b;
  for (const row& r : rows)
    if (auto d = b.push(r)) out.push_back(*d);
  if (auto d = b.flush()) out.push_back(*d);
  return out;
}

std::vector<dwell> extract_dwells(std::span<const row> rows, const flip_pair& pair) {
  std::vector<dwell> out;
  dwell_builder b;
  for (const row& r : rows)
    if (pair.holds(r.position))
      if (auto d = b.push(r)) out.push_back(*d);
  if (auto d = b.flush()) out.push_back(*d);
  return out;
}

}  // namespace gyroflip::method
