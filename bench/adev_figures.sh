#!/usr/bin/env bash
# Prints issue 4's figures: whole-process time and peak memory of `gyroflip adev` (OADEV, MDEV,
# TOTDEV, octave taus) on N float64 samples read from a .npy file, a STREAM-like copy bandwidth
# on this machine, and `gyroflip noise` on a 3-h 400-Hz log (4.32 M samples).
# Usage: bench/adev_figures.sh [N]   (default 1e8; 1000000000 for the 1e9 figures)
#   Needs 8 N bytes of disk in $TMPDIR (8 GB for 1e9; the file is deleted at the end) and as much
#   free memory for the page cache. RUNS=k repeats each timing k times (default 3; take the best).
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-100000000}
runs=${RUNS:-3}
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target gyroflip bench_allan >/dev/null
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
build/bench/bench_allan --write-npy "$tmp/y.npy" "$n"
build/bench/bench_allan --write-npy "$tmp/noise.npy" 4320000
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); load: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "copy bandwidth (memcpy of 400 MB, read + write): $(build/bench/bench_allan --copy-bandwidth 50000000) GB/s"
# The file must be in the page cache, as the issue measures: read it just before each run (the
# VM's proactive reclaim drops page-cache pages left untouched for about 30 s).
warm() { cat "$1" >/dev/null; }
for kind in oadev mdev totdev; do
  for ((r = 1; r <= runs; r++)); do
    warm "$tmp/y.npy"
    /usr/bin/time -f "adev --kind $kind, $n samples: %e s, peak RSS %M KB (user %U s, sys %S s)" \
      build/apps/gyroflip/gyroflip adev "$tmp/y.npy" --rate 100 --kind "$kind" --json >/dev/null
  done
done
for ((r = 1; r <= runs; r++)); do
  warm "$tmp/noise.npy"
  /usr/bin/time -f "noise, 4.32 M samples at 400 Hz: %e s, peak RSS %M KB" \
    build/apps/gyroflip/gyroflip noise "$tmp/noise.npy" --rate 400 --json >/dev/null
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
