#!/usr/bin/env bash
# scripts/demo as the README's first command (issue 21): one line per phase, saying what it does
# and about how long, every step and output there, and the time-stamp jitter note of the
# compensated series printed once (adev and noise both read that file; it printed twice). Runs the
# demo on the built gyroflip (DEMO_PREBUILT: no set-up, no build) into a temporary folder; .ci/run
# checks the set-up and build phases of a real run.
#   Usage: check_demo.sh SOURCE_DIR GYROFLIP
set -euo pipefail
src=$1
exe=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { cat "$work/log" >&2; echo "check_demo: $*" >&2; exit 1; }
DEMO_PREBUILT=$exe DEMO_OUT=$work/demo bash "$src/scripts/demo" >"$work/log" 2>&1 || fail "the demo failed"
for n in 1 2 3; do
  grep -q "^demo: \[$n/3\] ." "$work/log" || fail "no line for phase $n"
done
grep -qE '^demo: \[3/3\] .*(seconds|[0-9]+ s\))' "$work/log" || fail "phase 3 does not say how long"
grep -qE '^demo: done in [0-9]+ s$' "$work/log" || fail "no closing line"
for k in 1 2 3 4 5 6 7 8; do
  grep -q "^== $k\. " "$work/log" || fail "step $k missing"
done
notes=$(grep -c 'time stamps jitter' "$work/log" || true)
[ "$notes" -eq 1 ] || fail "the time-stamp jitter note printed $notes times"
for f in calibration.json compensated.csv sim_cal.csv sim_run.csv sim_calibration.json \
         sim_compensated.csv report/index.html report/report.pdf north.csv; do
  [ -s "$work/demo/$f" ] || fail "no $f"
done
# The phases a real run has: each says what it does and about how long.
grep -qE 'phase 1 ".*(minutes|min)' "$src/scripts/demo" || fail "phase 1 gives no time"
grep -qE 'phase 2 ".*about [0-9]+ min' "$src/scripts/demo" || fail "phase 2 gives no time"
# step 8: the four-position north finding prints a heading with its sigma and the limit
grep -qE '^heading [0-9.]+ deg \+- [0-9.]+ deg' "$work/log" || fail "no heading in step 8"
grep -q 'white-noise limit' "$work/log" || fail "no limit in step 8"
echo "demo: 3 phases, 8 steps, the jitter note once, all outputs"
