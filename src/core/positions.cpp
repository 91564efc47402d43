/// \file
/// \brief The table's positions (see positions.hpp).
#include "gyroflip/core/positions.hpp"

#include <cmath>

#include <fmt/format.h>

#include "gyroflip/core/error.hpp"

namespace gyroflip {

double angle_between_deg(double a_deg, double b_deg) noexcept {
  const double d = std::fmod(std::abs(a_deg - b_deg), 360.0);
  return d > 180.0 ? 360.0 - d : d;
}

position_table position_table::pair_0_180() {
  position_table t;
  t.positions_ = {{0, 0.0, table_position::unknown_steps},
                  {1, 180.0, table_position::unknown_steps}};
  return t;
}

result<position_table> position_table::of_angles(std::span<const double> angles_deg,
                                                 std::span<const std::int32_t> steps) {
  if (angles_deg.empty() || angles_deg.size() > max_positions)
    return usage_error(
        fmt::format("a table holds 1 to {} positions; got {}", max_positions, angles_deg.size()));
  if (!steps.empty() && steps.size() != angles_deg.size())
    return usage_error(fmt::format("{} steps for {} positions", steps.size(), angles_deg.size()));
  position_table t;
  for (std::size_t i = 0; i < angles_deg.size(); ++i) {
    const double a = angles_deg[i];
    if (!(a >= 0.0 && a < 360.0))
      return usage_error(fmt::format("position {} at {} deg: a table angle is in [0, 360)", i, a));
    for (std::size_t j = 0; j < i; ++j)
      if (angles_deg[j] == a)
        return usage_error(fmt::format(
            "positions {} and {} are both at {:g} deg: a table's angles differ", j, i, a));
    t.positions_.push_back(
        {static_cast<int>(i), a, steps.empty() ? table_position::unknown_steps : steps[i]});
  }
  return t;
}

result<position_table> position_table::of_visits(std::span<const double> angles_deg,
                                                 std::span<const std::int32_t> steps) {
  if (!steps.empty() && steps.size() != angles_deg.size())
    return usage_error(fmt::format("{} steps for {} positions", steps.size(), angles_deg.size()));
  std::vector<double> a;
  std::vector<std::int32_t> s;
  for (std::size_t i = 0; i < angles_deg.size(); ++i) {
    bool seen = false;
    for (const double x : a) seen = seen || x == angles_deg[i];
    if (seen) continue;
    a.push_back(angles_deg[i]);
    if (!steps.empty()) s.push_back(steps[i]);
  }
  return of_angles(a, s);
}

std::optional<int> position_table::index_of(double angle_deg, double tol_deg) const noexcept {
  std::optional<int> best;
  double best_off = 0.0;
  for (const auto& p : positions_) {
    const double off = angle_between_deg(angle_deg, p.angle_deg);
    if (off <= tol_deg && (!best || off < best_off)) {
      best = p.index;
      best_off = off;
    }
  }
  return best;
}

std::string position_table::describe(bool words) const {
  std::string out;
  for (std::size_t i = 0; i < positions_.size(); ++i) {
    if (i > 0) out += !words ? "," : i + 1 == positions_.size() ? " and " : ", ";
    out += fmt::format("{}", positions_[i].angle_deg);
  }
  return out;
}

}  // namespace gyroflip
