/// \file
/// \brief Slope read-offs of an Allan deviation curve (readoffs.hpp).
#include "gyroflip/analysis/readoffs.hpp"

#include <cmath>

namespace gyroflip::analysis {

namespace {

// sqrt(2 ln 2 / pi): the flicker floor of OADEV in units of B (IEEE 952 Annex C, eqn C.12).
constexpr double flicker_floor = 0.6643;

// The segment (i, i+1) whose log-log slope is nearest `slope`, within 0.25 of it, and the point
// (log tau, log dev) in its middle; nullopt when no segment is that close.
struct segment {
  double log_tau = 0.0, log_dev = 0.0;
};
std::optional<segment> nearest_slope(std::span<const deviation_point> pts, double slope) {
  std::optional<segment> best;
  double off = 0.25;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    const double lt0 = std::log(pts[i].tau_s), lt1 = std::log(pts[i + 1].tau_s);
    const double ld0 = std::log(pts[i].dev), ld1 = std::log(pts[i + 1].dev);
    if (!(lt1 > lt0) || !std::isfinite(ld0) || !std::isfinite(ld1)) continue;
    const double s = (ld1 - ld0) / (lt1 - lt0);
    if (std::abs(s - slope) <= off) {
      off = std::abs(s - slope);
      best = segment{0.5 * (lt0 + lt1), 0.5 * (ld0 + ld1)};
    }
  }
  return best;
}

}  // namespace

slope_readoffs read_off_terms(std::span<const deviation_point> pts) {
  slope_readoffs r;
  if (pts.size() < 2) return r;
  // sigma = N tau^-1/2: N = sigma(tau) sqrt(tau), i.e. the line's value at tau = 1 s.
  if (const auto s = nearest_slope(pts, -0.5)) {
    r.arw = std::exp(s->log_dev + 0.5 * s->log_tau);
    r.arw_from_tau_s = std::exp(s->log_tau);
  }
  // sigma = K sqrt(tau / 3): K = sigma(tau) sqrt(3 / tau), the line's value at tau = 3 s.
  if (const auto s = nearest_slope(pts, 0.5)) {
    r.rrw = std::exp(s->log_dev + 0.5 * (std::log(3.0) - s->log_tau));
    r.rrw_from_tau_s = std::exp(s->log_tau);
  }
  // The first local minimum, as the fit's floor (noise_fit.cpp): a later, lower minimum at long
  // tau rests on a few clusters (ADIS16405 X: 2 % lower at 1311 s than at 82 s, +-40 %).
  std::size_t low = 0;
  while (low + 1 < pts.size() && pts[low + 1].dev < pts[low].dev) ++low;
  r.floor_tau_s = pts[low].tau_s;
  r.floor_dev = pts[low].dev;
  r.floor_is_minimum = low + 1 < pts.size();
  r.bias_instability = r.floor_dev / flicker_floor;
  return r;
}

}  // namespace gyroflip::analysis
