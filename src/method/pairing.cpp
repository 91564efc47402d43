/// \file
/// \brief Dwells -> cycles, simple and abba pairings (see pairing.hpp).
///
/// The batch and streaming forms share the two kernels below and differ only in
/// bookkeeping, so they agree bit for bit (tested).
#include "gyroflip/method/pairing.hpp"

#include <cassert>
#include <cmath>

namespace gyroflip::method {
namespace {

using detail::estimate;

double mean_temp(double a, double b) {
  if (std::isnan(a)) return b;
  if (std::isnan(b)) return a;
  return 0.5 * (a + b);
}

// Simple pairing, paper eqn 7 (and the half-sum for the bias).
// `sign_a`: dwell a's sign (flip_pair::sign).
estimate half_difference(const dwell& a, const dwell& b, int sign_a) {
  return {0.5 * sign_a * (a.rate_dps - b.rate_dps), 0.5 * (a.rate_dps + b.rate_dps)};
}

// Three-point estimate at dwell `k`: its opposite orientation interpolated linearly in time
// from the neighbours `prev` and `next`, so a bias linear in time cancels exactly. `sign_k`: dwell
// k's sign.
estimate three_point(const dwell& prev, const dwell& k, const dwell& next, int sign_k) {
  const double span_s = next.time_s - prev.time_s;
  // Equal times (a degenerate record) fall back to the plain neighbour mean.
  const double w = span_s > 0.0 ? (k.time_s - prev.time_s) / span_s : 0.5;
  const double opposite = prev.rate_dps + w * (next.rate_dps - prev.rate_dps);
  return {0.5 * sign_k * (k.rate_dps - opposite), 0.5 * (k.rate_dps + opposite)};
}

// A cycle whose value comes from both dwells `a` and `b`: stamped at their mean time.
cycle make_cycle(const dwell& a, const dwell& b, const estimate& e) {
  return {0.5 * (a.time_s + b.time_s), e.rate_dps, e.bias_dps, mean_temp(a.temp_c, b.temp_c)};
}

// An abba cycle at the record's edge whose value is the estimate at dwell `k` alone: stamped
// at t_k, so that c = b(t) holds exactly for a linear bias there too.
cycle make_edge_cycle(const dwell& k, const estimate& e) {
  return {k.time_s, e.rate_dps, e.bias_dps, k.temp_c};
}

estimate average(const estimate& x, const estimate& y) {
  return {0.5 * (x.rate_dps + y.rate_dps), 0.5 * (x.bias_dps + y.bias_dps)};
}

}  // namespace

std::optional<cycle> cycle_builder::push(const dwell& d) {
  last_[0] = last_[1];
  last_[1] = last_[2];
  last_[2] = d;
  const std::size_t k = count_++;  // index of `d`
  if (pairing_ == pairing::simple) {
    if (k % 2 == 1)
      return make_cycle(last_[1], last_[2],
                        half_difference(last_[1], last_[2], pair_.sign(last_[1].position)));
    return std::nullopt;
  }
  if (k < 2) return std::nullopt;
  // The estimate at dwell k-1.
  const estimate e = three_point(last_[0], last_[1], last_[2], pair_.sign(last_[1].position));
  if ((k - 1) % 2 == 0) {  // first dwell of a cycle: keep until its partner has one too
    pending_ = e;
    return std::nullopt;
  }
  // k-1 is the second dwell of cycle (k-2, k-1); dwell k-2 has an estimate unless it is dwell 0.
  if (k - 2 == 0) return make_edge_cycle(last_[1], e);
  return make_cycle(last_[0], last_[1], average(pending_, e));
}

std::optional<cycle> cycle_builder::flush() {
  // abba with an even dwell count: the last cycle's second dwell has no right neighbour,
  // so only its first dwell's estimate (if that dwell is not dwell 0) is available.
  std::optional<cycle> out;
  if (pairing_ == pairing::abba && count_ >= 4 && count_ % 2 == 0)
    out = make_edge_cycle(last_[1], pending_);
  *this = cycle_builder{pairing_, pair_};
  return out;
}

std::vector<cycle> pair_cycles(std::span<const dwell> dwells, pairing p, flip_pair pair) {
  const auto sign = [&pair](const dwell& d) { return pair.sign(d.position); };
  const std::size_t n = dwells.size();
  std::vector<cycle> out;
  out.reserve(n / 2);
  for (std::size_t j = 0; 2 * j + 1 < n; ++j) {
    const dwell& a = dwells[2 * j];
    const dwell& b = dwells[2 * j + 1];
    assert(pair.holds(a.position) && pair.holds(b.position) && a.position != b.position);
    if (p == pairing::simple) {
      out.push_back(make_cycle(a, b, half_difference(a, b, sign(a))));
      continue;
    }
    const bool has_a = 2 * j >= 1;     // dwell 0 has no left neighbour
    const bool has_b = 2 * j + 2 < n;  // the last dwell has no right neighbour
    if (has_a && has_b) {
      out.push_back(make_cycle(a, b,
                               average(three_point(dwells[2 * j - 1], a, b, sign(a)),
                                       three_point(a, b, dwells[2 * j + 2], sign(b)))));
    } else if (has_b) {
      out.push_back(make_edge_cycle(b, three_point(a, b, dwells[2 * j + 2], sign(b))));
    } else if (has_a) {
      out.push_back(make_edge_cycle(a, three_point(dwells[2 * j - 1], a, b, sign(a))));
    }
  }
  return out;
}

}  // namespace gyroflip::method
