#!/usr/bin/env bash
# Runs ../shared/tools/contract-check.py (the issues' CLI contracts) against the built gyroflip.
# Exits 77 (ctest: skipped) when the shared folder is not beside the checkout.
set -u
exe=$1
shared=$2
if [ ! -f "$shared/tools/contract-check.py" ]; then
  echo "contract-check: $shared/tools/contract-check.py not found; skipped"
  exit 77
fi
exec python3 "$shared/tools/contract-check.py" "$exe"
