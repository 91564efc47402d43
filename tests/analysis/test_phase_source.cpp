// The phase rebuilt on demand (phase_source.hpp, issue 4: bounded memory): the phase against an
// all-long-double integration, any range read by any reader bit-identical to the whole phase,
// bounded reader buffers, block sums, errors, and every viewed sample handed back.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/phase_source.hpp"
#include "support/synth.hpp"

namespace gyroflip::analysis {
namespace {

constexpr std::size_t block = phase_source::block_points;

std::vector<double> white(std::size_t n, double bias, double sigma, std::uint64_t seed) {
  test::normal_source g(seed);
  std::vector<double> y(n);
  for (double& v : y) v = bias + sigma * g();
  return y;
}

TEST(PhaseSource, RateMatchesAnAllLongDoubleIntegration) {
  // A large bias over small noise: the mean removal and the long-double carries keep x to
  // ~1e-15 of its range (a double running sum without them would lose ~1e-9).
  const auto y = white(5 * block + 3, 1000.0, 3e-4, 11);
  long double mean = 0.0L;
  for (double v : y) mean += static_cast<long double>(v);
  mean /= static_cast<long double>(y.size());
  std::vector<long double> ref{0.0L};
  for (double v : y) ref.push_back(ref.back() + (static_cast<long double>(v) - mean));
  long double range = 0.0L;
  for (long double& r : ref) {
    r *= 0.01L;
    range = std::max(range, std::abs(r));
  }
  const auto x = phase_from_rate(y, 0.01);
  ASSERT_EQ(x.size(), y.size() + 1);
  EXPECT_EQ(x[0], 0.0);
  // A mean a few ulp(ybar) off (in double here, from the long-double sum in the reference) tilts
  // the phase by a linear trend that no deviation sees (differences cancel it) and makes x_M,
  // 0 with the exact mean, slightly nonzero. Without their trends the two agree to 1e-14 of the
  // range.
  const auto m = static_cast<long double>(y.size());
  const auto x_end = static_cast<long double>(x.back());
  EXPECT_LE(std::abs(x_end), m * 8.0L * 1.2e-13L * 0.01L);  // at most 8 ulp(1000) per step
  for (std::size_t k = 0; k < x.size(); ++k) {
    const auto f = static_cast<long double>(k) / m;
    const long double ours = static_cast<long double>(x[k]) - f * x_end;
    ASSERT_LE(std::abs(ours - (ref[k] - f * ref.back())), 1e-14L * range) << k;
  }
}

TEST(PhaseSource, AngleSamplesAreThePhase) {
  const auto a = white(3 * block + 7, 5.0, 1.0, 12);
  const span_samples s(a);
  const auto src = phase_source::make(s, input_kind::angle, 0.5);
  ASSERT_TRUE(src);
  ASSERT_EQ(src->size(), a.size());
  phase_reader r(*src);
  const auto x = r.read(0, a.size());
  EXPECT_TRUE(std::equal(x.begin(), x.end(), a.begin()));
  EXPECT_EQ(r.capacity(), 0u);  // a view, no buffer
}

// Reads [begin, begin + len) and compares it with the whole phase, bit for bit.
void expect_range(phase_reader& r, const std::vector<double>& full, std::size_t begin,
                  std::size_t len) {
  const auto v = r.read(begin, len);
  ASSERT_EQ(v.size(), len);
  for (std::size_t i = 0; i < len; ++i)
    ASSERT_EQ(v[i], full[begin + i]) << "range " << begin << "+" << len << " at " << i;
}

TEST(PhaseReader, AnyRangeIsBitIdenticalToTheWholePhase) {
  const auto y = white(12 * block + 5, 2.0, 1.0, 13);
  const span_samples s(y);
  const auto src = phase_source::make(s, input_kind::rate, 0.01);
  ASSERT_TRUE(src);
  const std::size_t n = src->size();
  std::vector<double> full;
  {
    phase_reader r(*src);
    const auto v = r.read(0, n);
    full.assign(v.begin(), v.end());
  }
  EXPECT_EQ(full, phase_from_rate(y, 0.01));
  // Fresh readers at and around block boundaries, single points and long ranges.
  for (std::size_t begin : {std::size_t{0}, std::size_t{1}, block - 1, block, block + 1,
                            4 * block - 1, 4 * block, 5 * block + 17, n - block - 1, n - 1})
    for (std::size_t len : {std::size_t{1}, std::size_t{2}, block, 4 * block + 3, n})
      if (begin + len <= n) {
        phase_reader r(*src);
        expect_range(r, full, begin, len);
      }
  // One reader moving forward with overlaps (a sliding window), then back, then jumping ahead.
  phase_reader r(*src);
  for (std::size_t b = 3; b + 3000 <= n; b += 1111) expect_range(r, full, b, 3000);
  expect_range(r, full, 5, 4 * block);
  expect_range(r, full, n - 7, 7);
  expect_range(r, full, 2 * block + 1, 1);
}

TEST(PhaseReader, BufferStaysBoundedOverALongRecord) {
  const auto y = white(std::size_t{1} << 18, 0.0, 1.0, 14);
  const span_samples s(y);
  const auto src = phase_source::make(s, input_kind::rate, 1.0);
  ASSERT_TRUE(src);
  phase_reader r(*src);
  constexpr std::size_t len = 5000;
  for (std::size_t b = 0; b + len <= src->size(); b += 4096) {
    (void)r.read(b, len);
    ASSERT_LE(r.capacity(), 2 * (len + 2 * block)) << b;
  }
  EXPECT_EQ(src->table_bytes(), ((src->size() + block - 1) / block) * 32u);
}

TEST(PhaseSource, OffsetSumMatchesTheDirectSum) {
  for (const input_kind in : {input_kind::rate, input_kind::angle}) {
    const auto y = white(9 * block + 11, 100.0, 1.0, 15);  // angle: an offset of 100
    const span_samples s(y);
    const auto src = phase_source::make(s, in, 0.1);
    ASSERT_TRUE(src);
    phase_reader all(*src);
    const auto x = all.read(0, src->size());
    phase_reader r(*src);
    for (std::size_t begin : {std::size_t{0}, std::size_t{5}, block, 3 * block - 2})
      for (std::size_t len : {std::size_t{1}, std::size_t{700}, 2 * block, 5 * block + 9}) {
        long double direct = 0.0L;
        for (std::size_t k = begin; k < begin + len; ++k)
          direct += static_cast<long double>(x[k]) - static_cast<long double>(x[0]);
        const long double got = src->offset_sum(begin, begin + len, r);
        EXPECT_LE(std::abs(got - direct), 1e-13L * (1.0L + std::abs(direct)))
            << (in == input_kind::rate ? "rate " : "angle ") << begin << "+" << len;
      }
  }
}

TEST(PhaseSource, ErrorsNameTheSample) {
  auto y = white(3 * block, 0.0, 1.0, 16);
  y[2049] = std::nan("");
  const span_samples s(y);
  for (const input_kind in : {input_kind::rate, input_kind::angle}) {
    const auto src = phase_source::make(s, in, 1.0);
    ASSERT_FALSE(src);
    EXPECT_EQ(src.err().message, "sample 2049 (0-based) is not finite");
  }
  const span_samples ok(std::span<const double>(y).first(2000));
  EXPECT_FALSE(phase_source::make(ok, input_kind::rate, 0.0));
  EXPECT_FALSE(phase_source::make(ok, input_kind::rate, INFINITY));
  EXPECT_TRUE(phase_source::make(ok, input_kind::rate, 1.0));
}

// Samples in memory that record, per page of 512 samples, whether a view has touched it since
// its last release, as a memory-mapped file would keep it resident.
class tracking_samples final : public sample_source {
 public:
  explicit tracking_samples(std::vector<double> y)
      : y_(std::move(y)), resident_((y_.size() + page - 1) / page, 0) {}
  [[nodiscard]] std::size_t size() const noexcept override { return y_.size(); }
  [[nodiscard]] std::span<const double> view(std::size_t begin,
                                             std::size_t count) const noexcept override {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (std::size_t p = begin / page; p * page < begin + count; ++p) {
      count_ += resident_[p] == 0 ? 1u : 0u;
      resident_[p] = 1;
    }
    peak_ = std::max(peak_, count_);
    return std::span<const double>(y_).subspan(begin, count);
  }
  void release(std::size_t begin, std::size_t end) const noexcept override {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (std::size_t p = begin / page; p * page < end && p < resident_.size(); ++p) {
      count_ -= resident_[p] != 0 ? 1u : 0u;
      resident_[p] = 0;
    }
  }
  [[nodiscard]] std::size_t release_step() const noexcept override { return 4096; }
  [[nodiscard]] std::size_t peak_samples() const { return peak_ * page; }
  [[nodiscard]] std::size_t resident_samples() const { return count_ * page; }

 private:
  static constexpr std::size_t page = 512;
  std::vector<double> y_;
  mutable std::mutex mutex_;
  mutable std::vector<char> resident_;
  mutable std::size_t count_ = 0;
  mutable std::size_t peak_ = 0;
};

TEST(PhaseSource, SweepsHandBackEverySampleTheyViewed) {
  // Bounded memory, tested through what a file source would keep resident: 2^23 samples (a
  // 64 MB file), each statistic's sweep and the noise identification. With a release step of
  // 4096 samples the readers may keep the chunks of 2^20 samples in work (at most three past the
  // lowest unfinished one, however the threads are scheduled), never most of the record.
  const std::size_t n = std::size_t{1} << 23;
  const tracking_samples s(white(n, 0.0, 1.0, 17));
  const auto src = phase_source::make(s, input_kind::rate, 0.01);
  ASSERT_TRUE(src);
  EXPECT_EQ(s.resident_samples(), 0u);
  for (const dev_kind k : {dev_kind::oadev, dev_kind::mdev, dev_kind::totdev, dev_kind::ohdev,
                           dev_kind::adev, dev_kind::hdev}) {
    auto pts = deviation(k, *src, {});
    ASSERT_TRUE(pts);
    add_confidence(*pts, k, *src, 0.683);
    EXPECT_EQ(s.resident_samples(), 0u) << to_string(k);
  }
  EXPECT_LE(s.peak_samples(), n / 2);
}

}  // namespace
}  // namespace gyroflip::analysis
