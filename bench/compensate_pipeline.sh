#!/usr/bin/env bash
# Usage: bench/compensate_pipeline.sh GYROFLIP ROWS (issue 33): `compensate --calibration` on a
# ROWS-row synthetic CSV (bench_compensate --write-csv), the calibration of a 200 000-row file of
# the same kind (its stationarity verdicts are judged again); best of 5 of the wall time and of the
# CPU time (perf stat task-clock: less sensitive to other work on the machine).

set -eu
gf=$1; rows=$2; bench=${BENCH:-build/bench/bench_compensate}
d=${TMPDIR:-/tmp}/gyroflip-compensate-pipeline; mkdir -p $d
[ -f $d/rows$rows.csv ] || $bench --write-csv $d/rows$rows.csv $rows
[ -f $d/cal.csv ] || $bench --write-csv $d/cal.csv 200000
$gf calibrate $d/cal.csv -o $d/cal.json >/dev/null 2>&1 || true
best_w=999; best_c=999
for i in 1 2 3 4 5; do
  out=$(perf stat -x, -e task-clock $gf compensate $d/rows$rows.csv --calibration $d/cal.json --json 2>&1 >/dev/null | grep task-clock)
  c=$(echo "$out" | cut -d, -f1); c=$(awk -v c=$c 'BEGIN{print c/1000}')
  s=$(date +%s.%N); $gf compensate $d/rows$rows.csv --calibration $d/cal.json --json >/dev/null 2>&1; e=$(date +%s.%N)
  w=$(awk -v s=$s -v e=$e 'BEGIN{print e-s}')
  best_w=$(awk -v a=$best_w -v b=$w 'BEGIN{print (b<a)?b:a}'); best_c=$(awk -v a=$best_c -v b=$c 'BEGIN{print (b<a)?b:a}')
done
awk -v n=$rows -v w=$best_w -v c=$best_c 'BEGIN{printf "%d rows: wall %.3f s = %.1f M rows/s; CPU %.3f s = %.1f M rows/s\n", n, w, n/w/1e6, c, n/c/1e6}'
