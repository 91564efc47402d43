// Earth-rate projection cost (a per-sample call in the simulator).
#include <benchmark/benchmark.h>

#include "gyroflip/earth/earth.hpp"

static void BM_EarthComponent(benchmark::State& state) {
  const auto axis = gyroflip::earth::ned_vector{0.6, 0.0, -0.8};
  double lat = 42.6;
  for (auto _ : state) {
    benchmark::DoNotOptimize(lat);
    benchmark::DoNotOptimize(gyroflip::earth::earth_rate_component_dps(lat, axis));
  }
}
BENCHMARK(BM_EarthComponent);
