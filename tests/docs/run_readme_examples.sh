#!/usr/bin/env bash
# Runs every ```sh block of README.md that calls `gyroflip` (not the scripts/ block, which installs
# packages) in an empty folder with the built gyroflip first on the PATH, stopping at the first
# failing line (issue 13: "the README's examples must run as written").
#   Usage: run_readme_examples.sh SOURCE_DIR GYROFLIP
set -euo pipefail
src=$1
exe=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir "$work/bin"
ln -s "$(realpath "$exe")" "$work/bin/gyroflip"
awk '/^```sh$/ {inblock=1; block=""; next}
     /^```$/ && inblock {inblock=0; if (block ~ /gyroflip / && block !~ /scripts\//) printf "%s", block; next}
     inblock {block = block $0 "\n"}' "$src/README.md" >"$work/examples.sh"
lines=$(grep -c '^gyroflip ' "$work/examples.sh" || true)
[ "$lines" -gt 0 ] || { echo "no gyroflip examples found in README.md" >&2; exit 1; }
cd "$work"
PATH="$work/bin:$PATH" bash -euo pipefail -x examples.sh >examples.out 2>&1 || {
  cat examples.out >&2
  echo "README example failed (above: the last + line ran last)" >&2
  exit 1
}
echo "README: $lines example commands ran"
