// A progress callback that throws cancels long work (core/progress.hpp; the Python module's
// Ctrl-C): the exception reaches the caller, the threads are joined (no std::terminate), and
// the same work runs again afterwards.
#include <cstddef>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/phase_source.hpp"

namespace {

using namespace gyroflip::analysis;

struct stop {};

TEST(Cancel, AThrowingProgressCallbackStopsASweepOnAllCores) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n01;
  std::vector<double> y(1 << 20);
  for (double& v : y) v = n01(rng);
  const span_samples s(y);
  auto x = phase_source::make(s, input_kind::rate, 1.0);
  ASSERT_TRUE(x);
  std::size_t calls = 0;
  const gyroflip::progress_fn cancel = [&](std::size_t, std::size_t) {
    if (++calls == 2) throw stop{};
  };
  for (const auto k : {dev_kind::oadev, dev_kind::mdev}) {
    calls = 0;
    EXPECT_THROW((void)deviation(k, *x, {}, cancel), stop) << to_string(k);
  }
  // ADEV of rate samples is one pass of block sums (allan.cpp, from_block_sums), and the
  // preparing pass reads 1 << 20 samples in 4 items: the other thread may take all items, so
  // the caller's thread may report only once (at the end; a fresh Debian 12 run had ADEV report
  // once); the first report cancels here.
  const gyroflip::progress_fn cancel_first = [](std::size_t, std::size_t) { throw stop{}; };
  EXPECT_THROW((void)deviation(dev_kind::adev, *x, {}, cancel_first), stop);
  EXPECT_THROW((void)phase_source::make(s, input_kind::rate, 1.0, cancel_first), stop);
  const auto again = deviation(dev_kind::oadev, *x, {});
  ASSERT_TRUE(again);
  EXPECT_NEAR(again->front().dev, 1.0, 5e-3);
}

}  // namespace
