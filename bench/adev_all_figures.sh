#!/usr/bin/env bash
# Prints issue 13 item 16's figure: `gyroflip adev --taus all` (OADEV, every averaging factor:
# 139 247 of them) on 556 990 phase points - the size of AllanTools' Cs5071A record, which is not
# available here, so white FM of the same length stands in (the work depends on N and the factor
# count, not on the values) - with intervals (noise identification + EDF at every factor) and
# with `--ci none`. Whole-process wall time, best of RUNS (default 3), and peak memory.
# Usage: bench/adev_all_figures.sh
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${RUNS:-3}
scripts/configure build
cmake --build build -j "$(nproc)" --target gyroflip bench_allan >/dev/null
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
build/bench/bench_allan --write-npy "$tmp/y.npy" 556990  # 556 990 phase points (angle input)
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load: $(cut -d' ' -f1-3 /proc/loadavg)"
# The issue's record is phase (angle input); a gyro's is rate. Both, with and without intervals.
for input in angle rate; do
  for ci in 0.683 none; do
    for ((r = 1; r <= runs; r++)); do
      /usr/bin/time -f "adev --input $input --taus all --ci $ci: %e s wall (%P CPU), peak RSS %M KB" \
        build/apps/gyroflip/gyroflip adev "$tmp/y.npy" --rate 1 --input "$input" --taus all \
        --ci "$ci" -o "$tmp/out.csv"
    done
  done
done
echo "factors: $(($(wc -l < "$tmp/out.csv") - 1)); load after: $(cut -d' ' -f1-3 /proc/loadavg)"
