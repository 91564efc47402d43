#!/usr/bin/env bash
# Simulator figures for docs/PERFORMANCE.md ("Simulator"): raw conversions/s on one core
# (full chain: every error term + ADC), multi-threaded Monte Carlo on all cores, and a
# one-week 500-Hz run through the CLI (dwell averages written).
#   Usage: bench/sim_figures.sh [BUILD_DIR]   (default build/, Release)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake --build "$build" -j2 --target bench_sim gyroflip >/dev/null
lscpu | grep -E "Model name" || true
"$build/bench/bench_sim" --benchmark_min_time=2 --benchmark_repetitions=3 \
  --benchmark_report_aggregates_only=true
out=$(mktemp)
start=$(date +%s.%N)
"$build/apps/gyroflip/gyroflip" simulate --sensor adxrs150 --duration 604800 --seed 1 -o "$out"
end=$(date +%s.%N)
echo "one week at 500 Hz (302.6 M conversions) via CLI: $(echo "$end - $start" | bc) s," \
  "$(grep -vc '^#' "$out") lines"
rm -f "$out"
