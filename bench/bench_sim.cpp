// Simulator throughput: the full chain (every error term on, ADC on) in raw conversions per
// second on one core, and a multi-threaded Monte Carlo (independent seeds, all cores).
// Figures and commands: docs/PERFORMANCE.md, section "Simulator"; script bench/sim_figures.sh.
// `bench_sim --run DURATION_S [SEED]` runs the full chain once without the benchmark library and
// prints the conversion count: the command that valgrind --tool=callgrind counts instructions of
// (repeatable regardless of machine load, unlike wall time).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include "gyroflip/rig/simulator.hpp"
#include "gyroflip/sensor/presets.hpp"

namespace {

using namespace gyroflip;

// ADXRS150 preset plus every term the preset leaves at zero, so nothing is skipped.
rig::simulation_config full_chain(std::uint64_t seed, double duration_s) {
  rig::simulation_config c;
  c.sensor = sensor::find_builtin("adxrs150")->params;
  c.sensor.rate_ramp_dps_per_s = 1e-6;
  c.sensor.quantisation_deg = 1e-6;
  c.sensor.g_sens_x_dps_per_g = 0.01;
  c.sensor.g_sens_tc_z_dps_per_g_c = 1e-4;
  c.sensor.cross_axis_z = 0.01;
  c.temperature = rig::profile::constant(4.0);  // != T_ref: temperature terms are active
  c.rate = rig::profile::constant(0.0);
  c.duration_s = duration_s;
  c.seed = seed;
  return c;
}

std::uint64_t run_one(std::uint64_t seed, double duration_s, double& sink, bool truth = true) {
  auto sim = rig::simulator::make(full_chain(seed, duration_s)).value();
  rig::sample_block b(4096, truth);
  std::uint64_t n = 0;
  while (std::size_t m = sim.fill(b)) {
    n += m;
    sink += b.rate_dps[m - 1];
  }
  return n;
}

void full_chain_runs(benchmark::State& state, bool truth) {
  double sink = 0.0;
  std::uint64_t total = 0;
  std::uint64_t seed = 1;
  for (auto _ : state) total += run_one(seed++, 2000.0, sink, truth);  // 1.0 M conversions
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(static_cast<std::int64_t>(total));
  state.counters["samples_per_s"] =
      benchmark::Counter(static_cast<double>(total), benchmark::Counter::kIsRate);
}

// The figure: every term, the ADC and the truth columns.
void BM_SimulateFullChain(benchmark::State& state) {
  full_chain_runs(state, true);
}
BENCHMARK(BM_SimulateFullChain)->Unit(benchmark::kMillisecond);

// The same model without the truth columns (a recording as the CLI writes it without --truth).
void BM_SimulateFullChainNoTruth(benchmark::State& state) {
  full_chain_runs(state, false);
}
BENCHMARK(BM_SimulateFullChainNoTruth)->Unit(benchmark::kMillisecond);

void BM_MonteCarloAllCores(benchmark::State& state) {
  const unsigned threads = std::max(1U, std::thread::hardware_concurrency());
  std::uint64_t total = 0;
  std::uint64_t base = 1000;
  for (auto _ : state) {
    std::vector<std::uint64_t> counts(threads);
    std::vector<double> sinks(threads);
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) {
      pool.emplace_back([&, t] {
        for (int r = 0; r < 4; ++r)
          counts[t] += run_one(base + 4 * t + static_cast<unsigned>(r), 500.0, sinks[t]);
      });
    }
    for (auto& th : pool) th.join();
    for (auto c : counts) total += c;
    base += 4 * threads;
    benchmark::DoNotOptimize(sinks.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(total));
  state.counters["threads"] = threads;
  state.counters["samples_per_s"] =
      benchmark::Counter(static_cast<double>(total), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_MonteCarloAllCores)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 3 && std::strcmp(argv[1], "--run") == 0) {
    double sink = 0.0;
    const std::uint64_t seed = argc >= 4 ? std::strtoull(argv[3], nullptr, 10) : 1;
    const std::uint64_t n = run_one(seed, std::strtod(argv[2], nullptr), sink);
    std::printf("%llu conversions (last rate %.9g)\n", static_cast<unsigned long long>(n), sink);
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
