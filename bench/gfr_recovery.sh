#!/usr/bin/env bash
# The .gfr reader against damage (issue 32; docs/RELIABILITY.md, "Damaged recordings"): 1 000
# random single-bit flips and 100 zeroed regions (1 B to 4 KiB) on
#   1. a recording made by `gyroflip record` from `gyroflip emulate` (600 s, two device resets,
#      bit errors on the line, seed 7), as written by this gyroflip (format 6);
#   2. the synthetic recording of bench/gfr_recovery.cpp in format 6 and in format 4 (as recorders
#      before issue 32 wrote it: no COPY records).
# Each prints the share of intact dwells recovered and the dwells mislabelled.
#   Usage: bench/gfr_recovery.sh [BUILD_DIR]   (default build/)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--help" ] || [ "${1:-}" = "-h" ]; then
  sed -n '2,9p' "$0"
  exit 0
fi
build=${1:-build}
[ -d "$build" ] || { echo "gfr_recovery.sh: no build folder $build" >&2; exit 2; }
cmake --build "$build" -j2 --target gfr_recovery gyroflip >/dev/null
exe="$build/apps/gyroflip/gyroflip"
work=$(mktemp -d)
emu=
cleanup() {
  [ -n "$emu" ] && kill "$emu" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
"$exe" emulate --pty --link "$work/rig" --speed max --seed 7 --fault-ber 1e-3 \
  --fault-reset-at 150.3,300.9 >"$work/emulate.log" 2>&1 &
emu=$!
for _ in $(seq 100); do [ -e "$work/rig" ] && break; sleep 0.1; done
"$exe" record --port "$work/rig" --duration 600 -o "$work/recorded.gfr" 2>"$work/record.log"
kill "$emu" 2>/dev/null || true
wait "$emu" 2>/dev/null || true
emu=
"$build/bench/gfr_recovery" --file "$work/recorded.gfr" --flips 1000 --zeros 100
"$build/bench/gfr_recovery" --format 6 --flips 1000 --zeros 100
"$build/bench/gfr_recovery" --format 4 --flips 1000 --zeros 100
