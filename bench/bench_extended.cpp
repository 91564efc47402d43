// The statistics of issue 23 on white rate noise, octave taus, intervals off (the goals:
// MTOTDEV, TTOTDEV, HTOTDEV, Theo1 on 1e5 points <= 2 s and on 1e6 <= 20 s; MTIE on 1e7 in
// bounded memory). `bench_extended --benchmark_filter=...`; docs/PERFORMANCE.md has the figures.
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/sensor/random.hpp"

namespace {

const std::vector<double>& white(std::size_t n) {
  static std::vector<double> y;
  if (y.size() != n) {
    gyroflip::sensor::normal_stream s(1, gyroflip::sensor::stream::user);
    y.resize(n);
    s.fill(y.data(), n);
  }
  return y;
}

void curve(benchmark::State& state, gyroflip::analysis::dev_kind k) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const auto& y = white(n);
  for (auto _ : state) {
    auto pts = gyroflip::analysis::deviation(k, y, gyroflip::analysis::input_kind::rate, 1.0, {});
    benchmark::DoNotOptimize(pts);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * state.range(0));
}

void BM_mtotdev(benchmark::State& s) {
  curve(s, gyroflip::analysis::dev_kind::mtotdev);
}
void BM_ttotdev(benchmark::State& s) {
  curve(s, gyroflip::analysis::dev_kind::ttotdev);
}
void BM_htotdev(benchmark::State& s) {
  curve(s, gyroflip::analysis::dev_kind::htotdev);
}
void BM_theo1(benchmark::State& s) {
  curve(s, gyroflip::analysis::dev_kind::theo1);
}
void BM_pdev(benchmark::State& s) {
  curve(s, gyroflip::analysis::dev_kind::pdev);
}
void BM_mtie(benchmark::State& s) {
  curve(s, gyroflip::analysis::dev_kind::mtie);
}
void BM_tierms(benchmark::State& s) {
  curve(s, gyroflip::analysis::dev_kind::tierms);
}

}  // namespace

BENCHMARK(BM_mtotdev)->Arg(100000)->Arg(1000000)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_ttotdev)->Arg(100000)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_htotdev)->Arg(100000)->Arg(1000000)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_theo1)->Arg(100000)->Arg(1000000)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_pdev)->Arg(1000000)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_mtie)->Arg(1000000)->Arg(10000000)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_tierms)->Arg(10000000)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_MAIN();
