#!/usr/bin/env bash
# Every program the tests, scripts/test, scripts/demo and .ci/run call must come from a package
# scripts/setup installs (or one those need), or from Debian's base system (Essential or Priority
# required, what debootstrap's minbase has): issue 21, `file` (cpack's dpkg-shlibdeps step) was on
# the developer machines by chance and missing on a fresh Debian 12. Skipped (77) without dpkg.
#   Usage: check_setup_covers_tools.sh SOURCE_DIR
set -euo pipefail
src=$1
command -v dpkg-query >/dev/null && command -v apt-cache >/dev/null || { echo "no dpkg: skipped"; exit 77; }

# The programs, by what calls them (keep in step when a test starts another program).
tools=(
  bash sh cat head sort uniq wc tr sed grep awk find mktemp realpath dirname basename timeout nproc
  date env id rm cp ln mkdir chmod stat           # scripts and test scripts
  cmake ninja c++ cc pkg-config git               # builds, the consumer project, lint
  /usr/bin/python3                                 # pytest suites, docs checks (Debian's, not PATH's)
  file dpkg-shlibdeps dpkg-deb cpack              # install_deb: cpack -G DEB and the package checks
  gnuplot pdfunite chromium                        # report, adev --plot, report_page_in_chromium
  xz gzip script                                   # reference data, a terminal for adev's table
  qemu-system-arm arm-none-eabi-gcc arm-none-eabi-size clang ld.lld llvm-size  # firmware
  clang-format clang-tidy cppcheck                 # scripts/lint (in .ci/run)
)

# What scripts/setup installs, and everything those depend on (no Recommends: setup passes
# --no-install-recommends).
mapfile -t listed < <(sed -n '/^packages=(/,/^)/p' "$src/scripts/setup" | sed 's/#.*//' |
  tr ' ' '\n' | grep -E '^[a-z0-9][a-z0-9.+-]+$' | grep -vx packages)
[ ${#listed[@]} -gt 20 ] || { echo "cannot read the package list of scripts/setup" >&2; exit 1; }
closure=$(apt-cache depends --recurse --no-recommends --no-suggests --no-conflicts --no-breaks \
  --no-replaces --no-enhances "${listed[@]}" | grep -E '^[a-z0-9]' | sort -u)
base=$(dpkg-query -W -f='${Package} ${Essential} ${Priority}\n' |
  awk '$2 == "yes" || $3 == "required" {print $1}' | sort -u)

missing=()
for t in "${tools[@]}"; do
  path=$(command -v "$t" || true)
  if [ -z "$path" ]; then
    missing+=("$t (not installed here)")
    continue
  fi
  # The package that holds the program: through symlinks and alternatives, and under /bin or
  # /usr/bin (a merged /usr registers files under either).
  pkg=
  for p in "$path" "$(readlink -f "$path")"; do
    for q in "$p" "/usr$p" "${p#/usr}"; do
      pkg=$(dpkg -S "$q" 2>/dev/null | grep -v "^diversion" | head -1 | cut -d: -f1 | cut -d, -f1 || true)
      [ -n "$pkg" ] && break 2
    done
  done
  if [ -z "$pkg" ]; then
    missing+=("$t ($path: in no package)")
    continue
  fi
  grep -qxF "$pkg" <<<"$closure" || grep -qxF "$pkg" <<<"$base" ||
    missing+=("$t (package $pkg: neither installed by scripts/setup nor in the base system)")
done
if [ ${#missing[@]} -gt 0 ]; then
  printf 'scripts/setup does not provide: %s\n' "${missing[@]}" >&2
  exit 1
fi
echo "scripts/setup provides all ${#tools[@]} programs the tests and scripts call"
