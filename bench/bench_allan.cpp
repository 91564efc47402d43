// Allan-family throughput (issue 4). `bench_allan --write-npy PATH N` writes N white-noise
// float64 samples as .npy for bench/adev_figures.sh; `--copy-bandwidth N` prints a STREAM-like
// copy figure (GB/s, bytes read + written) for comparing OADEV with the memory bandwidth.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "gyroflip/analysis/allan.hpp"
#include "gyroflip/analysis/confidence.hpp"
#include "gyroflip/analysis/phase_source.hpp"
#include "gyroflip/sensor/random.hpp"

namespace {

std::vector<double> white(std::size_t n) {
  gyroflip::sensor::normal_stream s(1, gyroflip::sensor::stream::user);
  std::vector<double> y(n);
  s.fill(y.data(), n);
  return y;
}

int write_npy(const char* path, std::size_t n) {
  std::string header =
      "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(n) + ",), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::FILE* f = std::fopen(path, "wb");
  if (f == nullptr) return 1;
  std::fwrite("\x93NUMPY\x01\x00", 1, 8, f);
  const unsigned char len[2] = {static_cast<unsigned char>(header.size() & 0xFF),
                                static_cast<unsigned char>(header.size() >> 8)};
  std::fwrite(len, 1, 2, f);
  std::fwrite(header.data(), 1, header.size(), f);
  gyroflip::sensor::normal_stream s(1, gyroflip::sensor::stream::user);
  std::vector<double> block(1 << 20);
  for (std::size_t done = 0; done < n; done += block.size()) {
    const std::size_t k = std::min(block.size(), n - done);
    s.fill(block.data(), k);
    std::fwrite(block.data(), sizeof(double), k, f);
  }
  return std::fclose(f) == 0 ? 0 : 1;
}

int copy_bandwidth(std::size_t n) {
  std::vector<double> a(n, 1.0), b(n, 0.0);
  double best = 1e30;
  for (int r = 0; r < 5; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    std::memcpy(b.data(), a.data(), n * sizeof(double));
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    best = std::min(best, s);
    a[static_cast<std::size_t>(r)] =
        b[n - 1 - static_cast<std::size_t>(r)];  // keep the copy observable
  }
  std::printf("%.2f\n", 2.0 * static_cast<double>(n * sizeof(double)) / best / 1e9);
  return 0;
}

void BM_Deviation(benchmark::State& state, gyroflip::analysis::dev_kind k) {
  const auto y = white(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state)
    benchmark::DoNotOptimize(
        gyroflip::analysis::deviation(k, y, gyroflip::analysis::input_kind::rate, 0.01, {}));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK_CAPTURE(BM_Deviation, oadev, gyroflip::analysis::dev_kind::oadev)
    ->Arg(1 << 22)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Deviation, mdev, gyroflip::analysis::dev_kind::mdev)
    ->Arg(1 << 22)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Deviation, totdev, gyroflip::analysis::dev_kind::totdev)
    ->Arg(1 << 22)
    ->Unit(benchmark::kMillisecond);

// Issue 13 item 16: every averaging factor (`--taus all`) of OADEV with the noise identification
// and EDF of every point, on 2^16 samples (16 383 factors): curves per second.
void BM_OadevAllTausWithIntervals(benchmark::State& state) {
  const auto y = white(static_cast<std::size_t>(state.range(0)));
  const gyroflip::analysis::span_samples samples(y);
  const auto src =
      *gyroflip::analysis::phase_source::make(samples, gyroflip::analysis::input_kind::rate, 1.0);
  const gyroflip::analysis::tau_spec all{gyroflip::analysis::tau_spec::set::all, {}};
  for (auto _ : state) {
    auto pts = *gyroflip::analysis::deviation(gyroflip::analysis::dev_kind::oadev, src, all);
    gyroflip::analysis::add_confidence(pts, gyroflip::analysis::dev_kind::oadev, src, 0.683);
    benchmark::DoNotOptimize(pts);
  }
}
BENCHMARK(BM_OadevAllTausWithIntervals)->Arg(1 << 16)->Unit(benchmark::kMillisecond);

// Rebuilding the phase of rate samples from the carries, as a far stream of a sweep reads it
// (4096 points a read, one reader, one thread): phase points per second.
void BM_PhaseRebuild(benchmark::State& state) {
  const auto y = white(static_cast<std::size_t>(state.range(0)));
  const gyroflip::analysis::span_samples samples(y);
  const auto src =
      *gyroflip::analysis::phase_source::make(samples, gyroflip::analysis::input_kind::rate, 0.01);
  for (auto _ : state) {
    gyroflip::analysis::phase_reader r(src);
    double s = 0.0;
    for (std::size_t b = 0; b + 4096 <= src.size(); b += 4096) s += r.read(b, 4096)[4095];
    benchmark::DoNotOptimize(s);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_PhaseRebuild)->Arg(1 << 22)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::strcmp(argv[1], "--write-npy") == 0)
    return write_npy(argv[2], static_cast<std::size_t>(std::strtoull(argv[3], nullptr, 10)));
  if (argc == 3 && std::strcmp(argv[1], "--copy-bandwidth") == 0)
    return copy_bandwidth(static_cast<std::size_t>(std::strtoull(argv[2], nullptr, 10)));
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
