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

}  // namespace
}  // namespace gyroflip::analysis
