#!/usr/bin/env bash
# `cmake --install build` and `cpack` must work after `scripts/demo` alone (issue 21: the demo built
# only the command, so both failed on the man pages and the Python module, after a half-install).
# Checks, in the build's own graph, that every file the install step takes from the build tree is
# made by the target scripts/demo builds: each installed file (or, for an installed folder, each
# file ninja makes in it) is among that target's inputs. Files the configure step writes (the
# package configuration, gyroflip.pc) exist without any build. Skipped (77) without ninja.
#   Usage: check_demo_builds_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
src=$2
[ -f "$build/build.ninja" ] && command -v ninja >/dev/null || { echo "not a ninja build: skipped"; exit 77; }
target=$(sed -n 's/.*cmake --build .* --target \([A-Za-z0-9_]*\).*/\1/p' "$src/scripts/demo" | head -1)
[ -n "$target" ] || { echo "scripts/demo names no --target" >&2; exit 1; }
# Every file in the target's part of the graph (its nodes: what it builds and reads).
made=$(ninja -C "$build" -t graph "$target" | grep -o 'label="[^"]*"' | sed 's/^label="//; s/"$//' |
  sed "s|^\([^/]\)|$build/\1|" | sort -u)
known=$(ninja -C "$build" -t targets all | sed 's/: .*//' | sed "s|^\([^/]\)|$build/\1|" | sort -u)
installed=$(find "$build" -name cmake_install.cmake -exec grep -ohE '"[^"]+"' {} + | tr -d '"' |
  grep "^$build/" | grep -v '\${' | sort -u)
[ -n "$installed" ] || { echo "no installed file found in $build/**/cmake_install.cmake" >&2; exit 1; }
missing=()
checked=0
for p in $installed; do
  p=${p%/}
  if grep -qxF "$p" <<<"$known"; then
    outputs=$p                                   # a file the build makes
  else
    outputs=$(grep "^$p/" <<<"$known" || true)   # a folder: what the build makes in it
  fi
  for o in $outputs; do
    checked=$((checked + 1))
    grep -qxF "$o" <<<"$made" || missing+=("${o#"$build"/}")
  done
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installed, but not built by scripts/demo (--target $target):" >&2
  printf '  %s\n' "${missing[@]}" >&2
  exit 1
fi
[ "$checked" -gt 5 ] || { echo "only $checked built files are installed: the check is broken" >&2; exit 1; }
echo "scripts/demo's target $target builds all $checked files the install step takes from the build"
