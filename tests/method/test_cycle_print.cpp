// A run's print and the copy found by content (fifth review of issue 31, F5): a copy with its
// dwell rates rounded, shifted by any number of dwells (trimmed at either end, split, an odd
// dwell that changes which dwells the pairing pairs) is found where it lies; independent runs are
// not (white dwells about a drifting bias and an alternating dN, fixed seeds).
#include <cmath>
#include <cstddef>
#include <random>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/method/cycle_print.hpp"

namespace gyroflip::method {
namespace {

std::vector<double> dwells(std::size_t n, unsigned seed, double sd = 0.0065) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> z(0.0, sd);
  std::vector<double> out(n);
  for (std::size_t k = 0; k < n; ++k)
    out[k] = 0.1 + 1e-5 * static_cast<double>(k) + (k % 2 == 0 ? 0.0031 : -0.0031) + z(g);
  return out;
}

TEST(CyclePrint, ACopyRoundedTrimmedOrSplitIsFoundWhereItLies) {
  const auto run = dwells(800, 1);
  const auto print = print_of(run);
  ASSERT_TRUE(print);
  EXPECT_EQ(print->q.size(), 798u);
  // Rounded to 1e-4 deg/s (0.01 of the scatter), dwells 57-656 only (an odd start).
  std::vector<double> copy(run.begin() + 57, run.begin() + 657);
  for (auto& z : copy) z = std::round(z * 1e4) / 1e4;
  const auto hit = find_in_print(copy, *print);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->first, 0u);
  EXPECT_EQ(hit->first_print, 57u);
  EXPECT_EQ(hit->length, 600u);
  // The second half of a split, after 80 dwells of another run: found at its alignment (the
  // other run's last dwells may match by chance, 14 % each).
  auto split = dwells(80, 2);
  split.insert(split.end(), run.begin() + 401, run.end());
  const auto second = find_in_print(split, *print);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->first_print - second->first, 321u);
  EXPECT_GE(second->length, 399u);
  // Too short a stretch is no copy (33 dwells: 31 print values; print_window is 32).
  EXPECT_FALSE(find_in_print(std::span(run).first(33), *print));
}

TEST(CyclePrint, IndependentRunsAreNoCopies) {
  std::size_t found = 0;
  std::vector<cycle_print> prints;
  for (unsigned s = 10; s < 20; ++s) prints.push_back(*print_of(dwells(600, s)));
  for (unsigned s = 100; s < 110; ++s) {
    const auto run = dwells(600, s);
    for (const auto& p : prints) found += find_in_print(run, p).has_value();
  }
  EXPECT_EQ(found, 0u);
  // Dwells without scatter have no print.
  EXPECT_FALSE(print_of(std::vector<double>(100, 0.0031)));
}

}  // namespace
}  // namespace gyroflip::method
