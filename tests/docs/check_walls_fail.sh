#!/usr/bin/env bash
# The module-walls check (cmake/check_includes.cmake) must fail on a wrong include, a CLI header in
# the library, a library string naming a CLI flag, a firmware file including a standard or host
# header, the library including firmware beyond the protocol and the AD7739 facts or the host side
# (issue 9); and pass on
# a clean tree (issue 13 items 18, 20, issue 8: a test that cannot fail is a defect, so this one
# makes the check fail on purpose).
#   Usage: check_walls_fail.sh SOURCE_DIR
set -euo pipefail
src=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rules="core:;earth:core;sensor:core"
run() { cmake -DROOT="$work" "-DRULES=$rules" -DSTAMP="$work/stamp" -P "$src/cmake/check_includes.cmake" >"$work/log" 2>&1; }
mkdir -p "$work/src/earth" "$work/src/core" "$work/include/gyroflip/earth" "$work/firmware/core" \
         "$work/firmware/ports/msp430f149"
printf '#include "gyroflip/core/error.hpp"\n#include "firmware/protocol/frame.hpp"\n' >"$work/src/earth/ok.cpp"
printf '#include "firmware/drivers/ad7739/convert.hpp"\n' >>"$work/src/earth/ok.cpp"
printf '#include <stdint.h>\n#include "protocol/frame.hpp"\n' >"$work/firmware/core/ok.cpp"
printf '#include <msp430.h>\n' >"$work/firmware/ports/msp430f149/ok.cpp"
run || { cat "$work/log"; echo "clean tree rejected" >&2; exit 1; }
caught=0
for bad in 'src/earth:#include "gyroflip/sensor/params.hpp"' 'src/earth:#include <CLI/CLI.hpp>' \
           'src/earth:const char* m = "give --rate HZ";' \
           'src/earth:#include "firmware/core/sequencer.hpp"' 'firmware/core:#include <cstdint>' \
           'firmware/core:#include "gyroflip/core/error.hpp"' 'firmware/core:#include <msp430.h>' \
           'src/earth:#include "host/emulator/emulator.hpp"'; do
  dir=${bad%%:*}
  printf '%s\n' "${bad#*:}" >"$work/$dir/bad.cpp"
  if run; then echo "not caught in $dir: ${bad#*:}" >&2; exit 1; fi
  rm "$work/$dir/bad.cpp"
  caught=$((caught + 1))
done
echo "module walls: the check catches all $caught violations"
