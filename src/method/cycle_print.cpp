/// \file
/// \brief A run's dwells as a print, and a copy found by content (see cycle_print.hpp).
#include "gyroflip/method/cycle_print.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "gyroflip/analysis/drift.hpp"

namespace gyroflip::method {

namespace {

// d_j = z_(j+2) - z_j of a run's dwell rates.
std::vector<double> print_values(std::span<const double> z) {
  std::vector<double> d;
  if (z.size() < 3) return d;
  d.reserve(z.size() - 2);
  for (std::size_t j = 0; j + 2 < z.size(); ++j) d.push_back(z[j + 2] - z[j]);
  return d;
}

}  // namespace

std::optional<cycle_print> print_of(std::span<const double> dwell_rates) {
  const auto d = print_values(dwell_rates);
  const std::size_t n = d.size();
  if (n < print_window) return std::nullopt;
  const auto ms = analysis::mean_and_std(d);
  const double mean = ms.mean, sd = ms.std;
  // No scatter (to the rounding of the mean): nothing to tell a copy by.
  if (!(sd > 1e-12 * std::abs(mean)) || !(sd > 0.0) || !std::isfinite(sd)) return std::nullopt;
  cycle_print p{mean, sd / print_steps_per_std, {}};
  p.q.reserve(n);
  // Clamped so that a wild value stays an int32: it matches nothing but itself then.
  for (const double x : d)
    p.q.push_back(
        static_cast<std::int32_t>(std::clamp(std::round((x - mean) / p.step_dps), -1e9, 1e9)));
  return p;
}

namespace {

// The first stretch of at least print_window matches along one alignment (value i of the run
// against printed value i + shift), scanning windows from their far end so that a mismatch
// skips the window (Boyer-Moore's habit): about len / window comparisons where nothing matches.
std::optional<print_match> along(std::span<const double> u, const cycle_print& p,
                                 std::ptrdiff_t shift) {
  const auto m = static_cast<std::ptrdiff_t>(p.q.size());
  const auto n = static_cast<std::ptrdiff_t>(u.size());
  const std::ptrdiff_t lo = std::max<std::ptrdiff_t>(0, -shift);
  const std::ptrdiff_t hi = std::min(n, m - shift);
  const auto w = static_cast<std::ptrdiff_t>(print_window);
  const auto same = [&](std::ptrdiff_t i) {
    return std::abs(u[static_cast<std::size_t>(i)] -
                    static_cast<double>(p.q[static_cast<std::size_t>(i + shift)])) <=
           print_match_steps;
  };
  std::ptrdiff_t i = lo;
  while (i + w <= hi) {
    std::ptrdiff_t k = i + w - 1;
    while (k >= i && same(k)) --k;
    if (k >= i) {
      i = k + 1;
      continue;
    }
    std::ptrdiff_t end = i + w;
    while (end < hi && same(end)) ++end;
    return print_match{static_cast<std::size_t>(i), static_cast<std::size_t>(i + shift),
                       static_cast<std::size_t>(end - i)};
  }
  return std::nullopt;
}

}  // namespace

std::optional<print_match> find_in_print(std::span<const double> dwell_rates,
                                         const cycle_print& print) {
  const auto d = print_values(dwell_rates);
  if (d.size() < print_window || print.q.size() < print_window || !(print.step_dps > 0.0))
    return std::nullopt;
  std::vector<double> u;
  u.reserve(d.size());
  for (const double x : d) u.push_back((x - print.offset_dps) / print.step_dps);
  std::optional<print_match> best;
  const auto n = static_cast<std::ptrdiff_t>(u.size());
  const auto m = static_cast<std::ptrdiff_t>(print.q.size());
  const auto w = static_cast<std::ptrdiff_t>(print_window);
  for (std::ptrdiff_t shift = w - n; shift <= m - w; ++shift)
    if (const auto hit = along(u, print, shift); hit && (!best || hit->length > best->length))
      best = hit;
  // A stretch of k values d_j spans k + 2 dwells.
  if (best) best->length += 2;
  return best;
}

}  // namespace gyroflip::method
