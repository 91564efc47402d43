#!/usr/bin/env bash
# Prints issue 2's figure: `gyroflip compensate` throughput in rows/s on a 10-million-row CSV,
# whole process (parsing included, best of 3), next to mawk summing one column of the same
# file, and the in-memory (no parsing) figure from Google Benchmark.
# Usage: bench/compensate_figures.sh [ROWS]   (run from the repository; builds Release first)
set -euo pipefail
cd "$(dirname "$0")/.."
rows=${1:-10000000}
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target gyroflip bench_compensate >/dev/null
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
csv=$tmp/rows.csv
build/bench/bench_compensate --write-csv "$csv" "$rows"
echo "file: $rows rows, $(du -m "$csv" | cut -f1) MB"

best() {  # best wall time of 3 runs of "$@", seconds
  local b=999999
  for _ in 1 2 3; do
    local s e
    s=$(date +%s.%N); "$@" >/dev/null; e=$(date +%s.%N)
    b=$(awk -v s="$s" -v e="$e" -v b="$b" 'BEGIN {d = e - s; print (d < b) ? d : b}')
  done
  echo "$b"
}
t_gf=$(best build/apps/gyroflip/gyroflip compensate "$csv" --delta-n 0.0123 --json)
t_awk=$(best mawk -F, '{s += $3} END {print s}' "$csv")
awk -v n="$rows" -v t="$t_gf" 'BEGIN {printf "gyroflip compensate (whole process, parsing included): %.2f s = %.1f M rows/s\n", t, n / t / 1e6}'
awk -v n="$rows" -v t="$t_awk" 'BEGIN {printf "mawk summing one column:                            %.2f s = %.1f M rows/s\n", t, n / t / 1e6}'
build/bench/bench_compensate --benchmark_filter='InMemory/10000000' --benchmark_min_time=1 2>/dev/null |
  awk '/BM_/ {for (i = 1; i <= NF; i++) if ($i ~ /items_per_second/) { v = $i; sub("items_per_second=", "", v); sub("/s$", "", v); print "in memory (no parsing):                             " v " rows/s" }}'
