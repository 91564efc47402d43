// The weighted least-squares solver (issue 13 item 17) against closed forms.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/analysis/least_squares.hpp"

namespace gyroflip::analysis {
namespace {

// Straight line through x = 0..4: X^T X = [[5, 10], [10, 30]], so (X^T W X)^-1 =
// [[0.6, -0.2], [-0.2, 0.1]] / w for equal weights w; a noise-free line is recovered exactly
// and chi^2 is the weighted sum of squared residuals.
TEST(LeastSquares, StraightLineClosedForm) {
  std::vector<double> a;
  std::vector<double> y;
  for (int x = 0; x < 5; ++x) {
    a.insert(a.end(), {1.0, static_cast<double>(x)});
    y.push_back(1.0 + 2.0 * x);
  }
  const std::vector<double> w(5, 4.0);
  const auto f = weighted_least_squares(a, 2, y, w);
  ASSERT_TRUE(f);
  EXPECT_NEAR(f->coeffs[0], 1.0, 1e-13);
  EXPECT_NEAR(f->coeffs[1], 2.0, 1e-13);
  EXPECT_NEAR(f->cov[0], 0.6 / 4, 1e-14);
  EXPECT_NEAR(f->cov[1], -0.2 / 4, 1e-14);
  EXPECT_NEAR(f->cov[2], -0.2 / 4, 1e-14);
  EXPECT_NEAR(f->cov[3], 0.1 / 4, 1e-14);
  EXPECT_NEAR(f->chi2, 0.0, 1e-20);
  // Residuals +1, -1, 0, 0, 0 at weight 4: chi^2 = 8 and the line shifts by their mean, 0, in
  // intercept and by sum(x r)/sum((x - 2)^2) = (0 - 1)/10 in slope.
  y[0] += 1.0;
  y[1] -= 1.0;
  const auto g = weighted_least_squares(a, 2, y, w);
  ASSERT_TRUE(g);
  EXPECT_NEAR(g->coeffs[1], 2.0 - 0.1, 1e-13);
  EXPECT_NEAR(g->coeffs[0], 1.0 + 0.2, 1e-13);
}

// Columns ten decades apart (the IEEE 952 basis 3/tau^2 ... tau^2/2 over tau = 0.01..1e4 s): the
// column scaling keeps the solve exact to rounding.
TEST(LeastSquares, ColumnsDecadesApart) {
  std::vector<double> a;
  std::vector<double> y;
  for (double tau = 0.01; tau < 2e4; tau *= 2) {
    a.insert(a.end(), {3.0 / (tau * tau), 1.0 / tau, tau * tau / 2.0});
    y.push_back(2e-9 * 3.0 / (tau * tau) + 5e-5 / tau + 7e-14 * tau * tau / 2.0);
  }
  const std::vector<double> w(y.size(), 1.0);
  const auto f = weighted_least_squares(a, 3, y, w);
  ASSERT_TRUE(f);
  EXPECT_NEAR(f->coeffs[0] / 2e-9, 1.0, 1e-9);
  EXPECT_NEAR(f->coeffs[1] / 5e-5, 1.0, 1e-9);
  EXPECT_NEAR(f->coeffs[2] / 7e-14, 1.0, 1e-9);
}

TEST(LeastSquares, RankDeficientAndBadInputAreErrors) {
  const std::vector<double> twice{1, 2, 2, 4, 3, 6};  // second column = 2 x first
  const std::vector<double> y{1, 2, 3};
  const std::vector<double> w{1, 1, 1};
  EXPECT_FALSE(weighted_least_squares(twice, 2, y, w));
  EXPECT_FALSE(weighted_least_squares(std::vector<double>{1, 2}, 2, std::vector<double>{1},
                                      std::vector<double>{1}));  // fewer rows than columns
  EXPECT_FALSE(
      weighted_least_squares(std::vector<double>{1, 1, 1}, 1, y, std::vector<double>{1, NAN, 1}));
}

}  // namespace
}  // namespace gyroflip::analysis
