// Compensate throughput (issue 2): rows per second with CSV parsing (read_cycles on a file)
// and without (rows already in memory); issue 33: the whole pipeline `gyroflip compensate
// --calibration` runs (workflow::compensate_file: the reader, the demodulator, the calibration's
// stationarity verdicts judged again and its fit to the recording checked, eqn 12, the summary).
// `bench_compensate --write-csv PATH N` writes the synthetic raw recording that
// bench/compensate_figures.sh times as a whole process.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "gyroflip/io/calibration_file.hpp"
#include "gyroflip/method/compensation.hpp"
#include "gyroflip/method/flip_stream.hpp"
#include "gyroflip/workflow/compensate.hpp"
#include "gyroflip/workflow/recordings.hpp"

namespace {

using gyroflip::method::row;

// Raw 500-Hz conversions as the paper's rig records them: 256 per dwell, then 8 rows with an
// empty angle while the table turns (1.79 s per 0/180 cycle). Noise from a fixed LCG.
std::vector<row> make_rows(std::size_t n) {
  std::vector<row> rows;
  rows.reserve(n);
  std::uint64_t state = 12345;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-53 - 0.5;
  };
  for (std::size_t k = 0; rows.size() < n; ++k) {
    const double t0 = static_cast<double>(k) * 0.895;
    const int position = k % 2 == 0 ? 0 : 1;  // the paper's table: 0 and 180 deg
    const double sign = k % 2 == 0 ? 1.0 : -1.0;
    for (int i = 0; i < 256 && rows.size() < n; ++i) {
      const double t = t0 + i * 0.002;
      rows.push_back(
          {t, position, sign * 0.0123 + 0.5 + 1e-6 * t + 0.01 * uniform(), 20.0 + t / 1e4, 1});
    }
    for (int j = 0; j < 8 && rows.size() < n; ++j)
      rows.push_back({t0 + 0.512 + j * 0.04, gyroflip::table_moving, 0.3, 20.0, 1});
  }
  return rows;
}

int write_csv(const char* path, std::size_t n) {
  std::FILE* f = std::fopen(path, "wb");
  if (f == nullptr) return 1;
  fmt::memory_buffer buf;
  fmt::format_to(std::back_inserter(buf), "time_s,angle_deg,rate_dps,temp_c,n_avg\n");
  for (const row& r : make_rows(n)) {
    if (r.position == gyroflip::table_moving)
      fmt::format_to(std::back_inserter(buf), "{:.4f},,{:.7f},{:.2f},1\n", r.time_s, r.rate_dps,
                     r.temp_c);
    else
      fmt::format_to(std::back_inserter(buf), "{:.4f},{:g},{:.7f},{:.2f},1\n", r.time_s,
                     r.position == 0 ? 0.0 : 180.0, r.rate_dps, r.temp_c);
    if (buf.size() > (1u << 20)) {
      std::fwrite(buf.data(), 1, buf.size(), f);
      buf.clear();
    }
  }
  std::fwrite(buf.data(), 1, buf.size(), f);
  return std::fclose(f) == 0 ? 0 : 1;
}

void BM_CompensateInMemory(benchmark::State& state) {
  const auto rows = make_rows(static_cast<std::size_t>(state.range(0)));
  const auto dn = gyroflip::method::constant_model(0.0123);
  for (auto _ : state) {
    std::vector<gyroflip::method::compensated_cycle> out;
    gyroflip::method::flip_stream s(gyroflip::method::pairing::abba);
    const auto sink = [&](const gyroflip::method::cycle& c) {
      out.push_back(gyroflip::method::compensate(c, dn));
    };
    for (const row& r : rows) s.push(r, sink);
    s.flush(sink);
    benchmark::DoNotOptimize(gyroflip::method::summarize(out));
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_CompensateInMemory)->Arg(1 << 20)->Arg(10'000'000)->Unit(benchmark::kMillisecond);

void BM_CompensateFromCsv(benchmark::State& state) {
  const std::string path = fmt::format("/tmp/gyroflip-bench-{}.csv", state.range(0));
  if (write_csv(path.c_str(), static_cast<std::size_t>(state.range(0))) != 0) {
    state.SkipWithError("cannot write the benchmark CSV");
    return;
  }
  const auto dn = gyroflip::method::constant_model(0.0123);
  for (auto _ : state) {
    auto rc = gyroflip::workflow::read_cycles(path, gyroflip::method::pairing::abba);
    if (!rc) {
      state.SkipWithError(rc.err().message.c_str());
      break;
    }
    std::vector<gyroflip::method::compensated_cycle> out;
    for (const auto& c : rc->cycles) out.push_back(gyroflip::method::compensate(c, dn));
    benchmark::DoNotOptimize(gyroflip::method::summarize(out));
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  std::remove(path.c_str());
}
BENCHMARK(BM_CompensateFromCsv)->Arg(1 << 20)->Arg(10'000'000)->Unit(benchmark::kMillisecond);

// A calibration of one stationary run whose stationarity test passed (what `calibrate -o`
// writes), so that compensate_file judges its verdicts again as the CLI does.
std::string calibration_json() {
  gyroflip::io::calibration_record rec;
  rec.pooled.delta_n_dps = 0.0123;
  rec.pooled.stderr_correlated_dps = 1e-4;
  rec.pooled.cycles = 1000;
  rec.pooled.temp_c = 20.0;
  gyroflip::method::stationarity st;
  st.checked = true;
  st.cycles = 1000;
  st.scatter_ratio = 1.0;
  st.scatter_limit = 1.25;
  st.scatter_low_limit = 0.68;
  st.drift_statistic = 1.0;
  st.step_limit_dps = 3e-4;
  rec.files.push_back({"cal.csv", rec.pooled, std::nullopt, st});
  return *gyroflip::io::to_json(rec);
}

void BM_CompensateFile(benchmark::State& state) {
  const std::string path = fmt::format("/tmp/gyroflip-bench-file-{}.csv", state.range(0));
  if (write_csv(path.c_str(), static_cast<std::size_t>(state.range(0))) != 0) {
    state.SkipWithError("cannot write the benchmark CSV");
    return;
  }
  auto dn = gyroflip::workflow::delta_n_of_json(calibration_json(), "cal.json");
  if (!dn) {
    state.SkipWithError(dn.err().message.c_str());
    return;
  }
  gyroflip::workflow::compensate_request req;
  req.file = path;
  req.delta_n = *dn;
  for (auto _ : state) {
    auto r = gyroflip::workflow::compensate_file(req);
    if (!r) {
      state.SkipWithError(r.err().message.c_str());
      break;
    }
    benchmark::DoNotOptimize(r->comp.summary);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  std::remove(path.c_str());
}
BENCHMARK(BM_CompensateFile)->Arg(2'000'000)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::strcmp(argv[1], "--write-csv") == 0)
    return write_csv(argv[2], static_cast<std::size_t>(std::strtoull(argv[3], nullptr, 10)));
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
