#!/usr/bin/env bash
# Installs the build into a temporary prefix and uses it as a user would (CTest: install_*):
#   check_install.sh prefix BUILD SRC PYTHON   cmake --install, then a consumer project through
#                                              find_package, the same through pkg-config, the
#                                              command, its man page, and `import gyroflip`
#   check_install.sh deb BUILD SRC PYTHON      cpack -G DEB, dpkg -x, then the command and
#                                              `import gyroflip` from the unpacked tree; Depends
set -euo pipefail
mode=$1 build=$2 src=$3 python=$4
tmp=$(mktemp -d "${TMPDIR:-/tmp}/gyroflip-install.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "check_install: $*" >&2; exit 1; }

import_check='import numpy as np, gyroflip
t, d, e, n = gyroflip.oadev([892, 809, 823, 798, 671, 644, 883, 903, 677], rate=1.0, data_type="freq", taus=[1, 2])
assert abs(d[0] / 91.22945 - 1) < 1e-6 and abs(d[1] / 85.95287 - 1) < 1e-6, d
import gyroflip.allantools as at
t2, d2, e2, n2 = at.oadev([892, 809, 823, 798, 671, 644, 883, 903, 677], data_type="freq", taus=[1, 2])
assert abs(d2[0] / 91.22945 - 1) < 1e-6, d2
print("python", gyroflip.__version__, gyroflip.__file__)'

if [ "$mode" = prefix ]; then
  p=$tmp/prefix
  cmake --install "$build" --prefix "$p" >"$tmp/install.log" 2>&1 || { cat "$tmp/install.log"; fail "cmake --install failed"; }
  "$p/bin/gyroflip" --version
  "$p/bin/gyroflip" earth --latitude 42.6 --axis north >/dev/null
  # A man page for every subcommand `gyroflip --help` lists (issue 21: report and reproduce had
  # none), each with its own NAME line (its one-line description) and a SEE ALSO naming every
  # other page.
  man=$p/share/man/man1
  pages=(gyroflip)
  while read -r sub; do pages+=("gyroflip-$sub"); done < <("$p/bin/gyroflip" --help |
    sed -n '/^Subcommands:/,$p' | sed -n 's/^  \([a-z][a-z0-9-]*\)  .*/\1/p')
  [ ${#pages[@]} -ge 13 ] || fail "only ${#pages[@]} pages expected from --help"
  names=()
  for page in "${pages[@]}"; do
    f=$man/$page.1
    [ -f "$f" ] || fail "no man page $page.1"
    grep -q "^\.TH ${page^^} 1" "$f" || fail "$page.1: no .TH line for ${page^^}"
    name=$(sed -n '/^\.SH NAME$/{n;p;}' "$f")
    case "$name" in "$page \\- "?*) ;; *) fail "$page.1: NAME line '$name'" ;; esac
    names+=("${name#* \\- }")
    for other in "${pages[@]}"; do
      [ "$other" = "$page" ] && continue
      sed -n '/^\.SH SEE ALSO$/,$p' "$f" | grep -qF "\fB$other\fR(1)" ||
        fail "$page.1: SEE ALSO does not name $other(1)"
    done
  done
  [ "$(printf '%s\n' "${names[@]}" | sort -u | wc -l)" -eq ${#pages[@]} ] ||
    fail "man pages share a NAME line: $(printf '%s | ' "${names[@]}")"
  [ -z "$(find "$man" -name '*.1' | grep -vxF -f <(printf "$man/%s.1\n" "${pages[@]}"))" ] ||
    fail "man pages for no subcommand: $(ls "$man")"
  # The consumer project, through find_package.
  cmake -S "$src/tests/install/consumer" -B "$tmp/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$p" >"$tmp/configure.log" 2>&1 || { cat "$tmp/configure.log"; fail "find_package(gyroflip) failed"; }
  cmake --build "$tmp/consumer" >"$tmp/build.log" 2>&1 || { cat "$tmp/build.log"; fail "the consumer did not build"; }
  "$tmp/consumer/consumer"
  # The same program through pkg-config.
  pc=$(find "$p" -name gyroflip.pc)
  flags=$(PKG_CONFIG_PATH=$(dirname "$pc") pkg-config --cflags --libs gyroflip)
  # shellcheck disable=SC2086
  c++ -std=c++20 -O1 "$src/tests/install/consumer/main.cpp" -o "$tmp/consumer_pc" $flags ||
    fail "the consumer did not build with pkg-config's flags: $flags"
  "$tmp/consumer_pc" >/dev/null
  # The Python module where this prefix's interpreter path puts it.
  pydir=$(dirname "$(dirname "$(find "$p" -path '*/dist-packages/gyroflip/__init__.py')")")
  case "$pydir" in "$p"/lib/python3*/dist-packages) ;; *) fail "Python module in $pydir" ;; esac
  (cd "$tmp" && PYTHONPATH=$pydir "$python" -c "$import_check")
elif [ "$mode" = deb ]; then
  (cd "$build" && cpack -G DEB -B "$tmp/pkg" >"$tmp/cpack.log" 2>&1) || { cat "$tmp/cpack.log"; fail "cpack failed"; }
  deb=$(find "$tmp/pkg" -maxdepth 1 -name 'gyroflip_*.deb')
  [ -n "$deb" ] || fail "no .deb made"
  depends=$(dpkg-deb -f "$deb" Depends)
  echo "Depends: $depends"
  for lib in libc6 libstdc++6 libfmt9 libhdf5 python3-numpy; do
    grep -q "$lib" <<<"$depends" || fail "Depends lacks $lib"
  done
  # docs/INSTALL.md lists the package's relations: the same package names (issue 21: it lacked
  # libssl3, and report's gnuplot and PDF makers were in no field at all).
  names() { tr ',' '\n' | sed 's/(.*)//; s/^ *//; s/ *$//' | { grep -v '^$' || true; } | sort -u; }
  for field in Depends Recommends Suggests; do
    documented=$(sed -n "s/^$field: //p" "$src/docs/INSTALL.md" | names)
    packaged=$(dpkg-deb -f "$deb" "$field" | names)
    [ -n "$documented" ] || fail "docs/INSTALL.md has no '$field:' line"
    [ "$documented" = "$packaged" ] ||
      fail "$field: docs/INSTALL.md says $(echo $documented), the .deb $(echo $packaged)"
  done
  dpkg-deb -c "$deb" >"$tmp/contents"
  grep -q './usr/lib/python3/dist-packages/gyroflip/allantools/allantools.py' "$tmp/contents" && grep -q './usr/lib/python3/dist-packages/gyroflip/__init__.py' "$tmp/contents" ||
    fail "the Python module is not in /usr/lib/python3/dist-packages"
  dpkg -x "$deb" "$tmp/root"
  "$tmp/root/usr/bin/gyroflip" --version
  "$tmp/root/usr/bin/gyroflip" adev "$src/tests/vectors/demo/cal_stationary_20c.csv" --ignore-flip >/dev/null
  (cd "$tmp" && PYTHONPATH=$tmp/root/usr/lib/python3/dist-packages "$python" -c "$import_check") >"$tmp/py.out"
  grep -q "$tmp/root/usr/lib/python3/dist-packages/gyroflip" "$tmp/py.out" ||
    fail "import gyroflip did not load the unpacked module: $(cat "$tmp/py.out")"
  echo "deb ok: $(basename "$deb")"
else
  fail "mode must be prefix or deb"
fi
