#!/usr/bin/env bash
# Prints issue 4's figures: whole-process time and peak memory of `gyroflip adev` (OADEV, MDEV,
# TOTDEV, octave taus) on N float64 samples read from a .npy file, a STREAM-like copy bandwidth
# on this machine, and `gyroflip noise` on a 3-h 400-Hz log (4.32 M samples).
# Usage: bench/adev_figures.sh [N]   (default 1e8; needs 8 N bytes of disk in $TMPDIR)
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-100000000}
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target gyroflip bench_allan >/dev/null
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
build/bench/bench_allan --write-npy "$tmp/y.npy" "$n"
build/bench/bench_allan --write-npy "$tmp/noise.npy" 4320000
echo "copy bandwidth (memcpy of 400 MB, read + write): $(build/bench/bench_allan --copy-bandwidth 50000000) GB/s"
for kind in oadev mdev totdev; do
  /usr/bin/time -f "adev --kind $kind, $n samples: %e s, peak RSS %M KB" \
    build/apps/gyroflip/gyroflip adev "$tmp/y.npy" --rate 100 --kind "$kind" --json >/dev/null
done
/usr/bin/time -f "noise, 4.32 M samples at 400 Hz: %e s, peak RSS %M KB" \
  build/apps/gyroflip/gyroflip noise "$tmp/noise.npy" --rate 400 --json >/dev/null
