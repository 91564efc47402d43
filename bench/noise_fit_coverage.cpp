/// \file
/// \brief Issue 34 item 1's goal measured over many seeds: on static records through the
/// simulator's sensor with an ADIS16405-like anti-alias filter (first-order low-pass at 28 Hz,
/// 100 Hz samples) and known N and B, how often the default noise fit's N lies within 2 % of
/// the truth and inside its interval, against the fit over every tau (before issue 34).
///
///   build/bench/noise_fit_coverage [SEEDS=200] [SAMPLES=1048576] [LINE_DPS=0]
///
/// Prints one line per fit: seeds, N/truth mean and standard deviation, the fraction within 2 %,
/// the fraction whose 68.3 % interval holds the truth, and Q resolved. Figures:
/// docs/PERFORMANCE.md.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "gyroflip/analysis/noise.hpp"
#include "gyroflip/analysis/sample_source.hpp"
#include "support/synth.hpp"

namespace {

using namespace gyroflip::analysis;

struct tally {
  int seeds = 0, within2 = 0, inside = 0, q = 0;
  double sum = 0.0, sum2 = 0.0;
  void add(const noise_terms& t, double truth) {
    const double r = t.arw.value / truth;
    ++seeds;
    sum += r;
    sum2 += r * r;
    within2 += std::abs(r - 1.0) <= 0.02 ? 1 : 0;
    inside += t.arw.resolved && t.arw.lo <= truth && truth <= t.arw.hi ? 1 : 0;
    q += t.quantization.resolved ? 1 : 0;
  }
  void print(const char* name) const {
    const double n = seeds;
    const double mean = sum / n;
    std::printf(
        "%-28s seeds %d  N/truth %.4f +- %.4f  within 2 %%: %.3f  interval holds: %.3f  Q "
        "resolved: %.3f\n",
        name, seeds, mean, std::sqrt(std::max(sum2 / n - mean * mean, 0.0)), within2 / n,
        inside / n, q / n);
  }
};

}  // namespace

int main(int argc, char** argv) {
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 200;
  const std::size_t samples = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : (1u << 20);
  const double line_dps = argc > 3 ? std::atof(argv[3]) : 0.0;
  constexpr double n_true = 0.04, b_true = 0.008, dt = 0.01;
  tally fresh, old;
  for (int s = 1; s <= seeds; ++s) {
    const auto y = gyroflip::test::static_gyro_rates(n_true, b_true, 0.0, 28.0, dt, samples,
                                                     static_cast<std::uint64_t>(s), line_dps, 20.0);
    const span_samples src(y);
    const auto x = phase_source::make(src, input_kind::rate, dt);
    if (!x) return 1;
    tau_range r;
    const auto a = analyse_noise(*x, 0.683, r);
    r.detect_shaping = false;
    const auto b = analyse_noise(*x, 0.683, r);
    if (!a || !b) return 1;
    fresh.add(a->terms, n_true);
    old.add(b->terms, n_true);
  }
  fresh.print("default (issue 34)");
  old.print("every tau fitted (before)");
  return 0;
}
