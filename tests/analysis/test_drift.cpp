// Paper drift metrics: mean/std and moving-mean extremes against closed forms.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/analysis/drift.hpp"

namespace gyroflip::analysis {
namespace {

TEST(Drift, MeanAndStdClosedForm) {
  const std::vector<double> v{2, 4, 4, 4, 5, 5, 7, 9};
  const auto s = mean_and_std(v);
  EXPECT_DOUBLE_EQ(s.mean, 5.0);
  EXPECT_NEAR(s.std, std::sqrt(32.0 / 7.0), 1e-15);
  EXPECT_EQ(mean_and_std(std::vector<double>{3.0}).std, 0.0);
}

// The element of rank n/2 of the sorted values, whatever their order.
TEST(Drift, UpperMedianIsTheElementOfRankHalfN) {
  EXPECT_EQ(upper_median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(upper_median({4.0, 1.0, 3.0, 2.0}), 3.0);  // upper of the middle two
  EXPECT_EQ(upper_median({7.5}), 7.5);
}

TEST(Drift, MeanAndStdSurvivesLargeOffset) {
  // A naive sum-of-squares loses every digit here; the two-pass form keeps them.
  std::vector<double> v;
  for (int i = 0; i < 1000; ++i) v.push_back(1e9 + (i % 2 == 0 ? 1.0 : -1.0));
  EXPECT_NEAR(mean_and_std(v).std, std::sqrt(1000.0 / 999.0), 1e-9);
}

TEST(Drift, MovingMeanOfRampHasRangeOfRamp) {
  // y = a t sampled every 1 s: the trailing 10-s mean at t_j is a (t_j - 4.5); its range
  // over j = 10..99 is a * 89.
  std::vector<double> t, y;
  for (int i = 0; i < 100; ++i) {
    t.push_back(i);
    y.push_back(0.5 * i);
  }
  const auto r = moving_mean_extremes(t, y, 10.0);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->windows, 90u);
  EXPECT_NEAR(r->min, 0.5 * 5.5, 1e-12);
  EXPECT_NEAR(r->range(), 0.5 * 89, 1e-12);
}

TEST(Drift, ShortRecordHasNoWindowAndConstantHasNoRange) {
  const std::vector<double> t{0, 1, 2}, y{1, 1, 1};
  EXPECT_FALSE(moving_mean_extremes(t, y, 10.0));
  const auto r = moving_mean_extremes(t, y, 1.0);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->range(), 0.0);
}

// Regression (issue 13 item 1, 2026-11-23): with t - window == t in floating point the window
// start ran past the end of the arrays (heap-buffer-overflow under ASan, `drift -nan` in
// Release). Unix-epoch nanosecond stamps and a 1e-300-s window both did it.
TEST(Drift, WindowBelowTimeResolutionHasNoDrift) {
  const std::vector<double> t(6, 1.7e18), y{1, -1, 1, -1, 1, -1};
  EXPECT_FALSE(moving_mean_extremes(t, y, 100.0));
  const std::vector<double> t2{0, 1, 2, 3}, y2{1, 2, 3, 4};
  EXPECT_FALSE(moving_mean_extremes(t2, y2, 1e-300));
  // Epoch seconds (1.7e9, resolution 2.4e-7 s) still resolve a 100-s window.
  std::vector<double> t3, y3;
  for (int i = 0; i < 300; ++i) {
    t3.push_back(1.7e9 + i);
    y3.push_back(i % 2);
  }
  const auto r = moving_mean_extremes(t3, y3, 100.0);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->windows, 200u);      // j = 100..299
  EXPECT_NEAR(r->max, 0.5, 1e-12);  // (t_j - 100, t_j] holds 100 samples, 50 of them ones
  EXPECT_NEAR(r->range(), 0.0, 1e-12);
}

}  // namespace
}  // namespace gyroflip::analysis
