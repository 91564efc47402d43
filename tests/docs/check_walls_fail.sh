#!/usr/bin/env bash
# The module-walls check (cmake/check_includes.cmake) must fail on a wrong include, a CLI header in
# the library and a library string naming a CLI flag, and pass on a clean tree (issue 13 items 18,
# 20: a test that cannot fail is a defect, so this one makes the check fail on purpose).
#   Usage: check_walls_fail.sh SOURCE_DIR
set -euo pipefail
src=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rules="core:;earth:core;sensor:core"
run() { cmake -DROOT="$work" "-DRULES=$rules" -DSTAMP="$work/stamp" -P "$src/cmake/check_includes.cmake" >"$work/log" 2>&1; }
mkdir -p "$work/src/earth" "$work/src/core" "$work/include/gyroflip/earth"
printf '#include "gyroflip/core/error.hpp"\n' >"$work/src/earth/ok.cpp"
run || { cat "$work/log"; echo "clean tree rejected" >&2; exit 1; }
for bad in '#include "gyroflip/sensor/params.hpp"' '#include <CLI/CLI.hpp>' \
           'const char* m = "give --rate HZ";'; do
  printf '%s\n' "$bad" >"$work/src/earth/bad.cpp"
  if run; then echo "not caught: $bad" >&2; exit 1; fi
done
echo "module walls: the check catches all 3 violations"
