/// \file
/// \brief Theo1, PDEV, MTIE and TIE rms at one averaging factor (see extended.hpp).
#include <algorithm>
#include <deque>
#include <vector>

#include "extended.hpp"
#include "parallel.hpp"

namespace gyroflip::analysis::detail {
namespace {

// Terms per work item of the direct sums (Theo1): enough that a thread's start costs nothing.
constexpr std::size_t item_points = 4096;

}  // namespace

sum_terms theo1_sum(std::span<const double> x, std::size_t m) {
  const std::size_t n = x.size();
  if (m < 2 || m % 2 != 0 || m >= n) return {};
  const std::size_t h = m / 2;
  const std::size_t outer = n - m;
  const std::size_t items = (outer + item_points - 1) / item_points;
  std::vector<long double> part(items, 0.0L);
  std::vector<double> weight(
      h);  // 1 / (m/2 - d): a multiplication in the inner loop, not a division
  for (std::size_t d = 0; d < h; ++d) weight[d] = 1.0 / static_cast<double>(h - d);
  // Direct: (N - m) m / 2 terms. Each i reads x_i, x_{i+m} and the pairs around i + m/2.
  for_each_item(items, worker_count(outer * h), [&](std::size_t, std::size_t it) {
    const std::size_t i0 = it * item_points;
    const std::size_t i1 = std::min(outer, i0 + item_points);
    long double acc = 0.0L;
    for (std::size_t i = i0; i < i1; ++i) {
      const double a = x[i] + x[i + m];
      const double* c = x.data() + i + h;
      double s0 = 0.0, s1 = 0.0;
      std::size_t d = 0;
      for (; d + 2 <= h; d += 2) {
        const double e0 = a - c[-static_cast<std::ptrdiff_t>(d)] - c[d];
        const double e1 = a - c[-static_cast<std::ptrdiff_t>(d + 1)] - c[d + 1];
        s0 += e0 * e0 * weight[d];
        s1 += e1 * e1 * weight[d + 1];
      }
      for (; d < h; ++d) {
        const double e = a - c[-static_cast<std::ptrdiff_t>(d)] - c[d];
        s0 += e * e * weight[d];
      }
      acc += static_cast<long double>(s0 + s1);
    }
    part[it] = acc;
  });
  long double sum = 0.0L;
  for (long double p : part) sum += p;
  return {sum, outer * h};
}

sum_terms pdev_sum(std::span<const double> x, std::size_t m) {
  const std::size_t n = x.size();
  if (m < 2 || n < 2 * m + 1) return {};
  const std::size_t terms = n - 2 * m;
  // P_i = sum_k c_k (x_{i+k} - x_{i+k+m}), c_k = (m-1)/2 - k. Moving i by one: since
  // c_{k-1} - c_k = 1, P_{i+1} = P_i - c_0 (y_i + y_{i+m}) + sum_{k=1}^{m-1} y_{i+k}, y_t = x_t -
  // x_{t+m}; the inner sum slides too. Both are recomputed exactly every 4096 steps so that
  // rounding cannot grow.
  const double c0 = 0.5 * static_cast<double>(m - 1);
  const auto y = [&](std::size_t t) { return x[t] - x[t + m]; };
  long double sum = 0.0L;
  long double p = 0.0L, inner = 0.0L;
  for (std::size_t i = 0; i < terms; ++i) {
    if (i % 4096 == 0) {
      p = 0.0L;
      inner = 0.0L;
      for (std::size_t k = 0; k < m; ++k) {
        p += static_cast<long double>((c0 - static_cast<double>(k)) * y(i + k));
        if (k >= 1) inner += static_cast<long double>(y(i + k));
      }
    }
    sum += p * p;
    if (i + 1 < terms) {
      p += -static_cast<long double>(c0) *
               (static_cast<long double>(y(i)) + static_cast<long double>(y(i + m))) +
           inner;
      inner += static_cast<long double>(y(i + m)) - static_cast<long double>(y(i + 1));
    }
  }
  return {sum, terms};
}

sum_terms mtie_value(std::span<const double> x, std::size_t m) {
  const std::size_t n = x.size();
  if (m == 0 || n < m + 1) return {};
  // Sliding-window maximum and minimum over m + 1 points with two monotonic deques of indices:
  // every index enters and leaves each once, so O(N) whatever m.
  std::deque<std::size_t> hi, lo;
  double best = 0.0;
  for (std::size_t t = 0; t < n; ++t) {
    while (!hi.empty() && x[hi.back()] <= x[t]) hi.pop_back();
    while (!lo.empty() && x[lo.back()] >= x[t]) lo.pop_back();
    hi.push_back(t);
    lo.push_back(t);
    if (t < m) continue;
    const std::size_t first = t - m;  // the window is x[t - m, t]
    while (hi.front() < first) hi.pop_front();
    while (lo.front() < first) lo.pop_front();
    best = std::max(best, x[hi.front()] - x[lo.front()]);
  }
  return {static_cast<long double>(best), n - m};
}

sum_terms tie_sum(std::span<const double> x, std::size_t m) {
  const std::size_t n = x.size();
  if (m == 0 || n < m + 1) return {};
  long double sum = 0.0L;
  double block = 0.0;
  for (std::size_t i = 0; i + m < n; ++i) {
    const double d = x[i + m] - x[i];
    block += d * d;
    if (i % 4096 == 4095) {
      sum += static_cast<long double>(block);
      block = 0.0;
    }
  }
  return {sum + static_cast<long double>(block), n - m};
}

}  // namespace gyroflip::analysis::detail
