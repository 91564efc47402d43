#!/usr/bin/env python3
"""How often Theo1's printed interval holds the truth where fewer than 30 decimated points are left
to identify the noise on (docs/ANALYSIS.md, "Theo1"): an accuracy figure, not a speed one.

For each power-law type (white PM, flicker PM, white FM, flicker FM, random-walk FM) RECORDS
records of N phase points are made (white PM: white samples; white and random-walk FM: one and two
cumulative sums; flicker PM and FM: Kasdin's generator of gyroflip.allantools.noise, seeded).
Theo1 is computed at every even factor m with (N - 1)/m + 1 < 30 from a short list, with the
identified type (the default) and with the true type (`alpha=`). The truth at m is the RMS of the
records' values; coverage is the share of records whose 68.3 % interval holds it.

Usage (Debian's interpreter, after a build):
    /usr/bin/python3 bench/theo1_coverage.py [build/python] [N] [RECORDS]
Defaults: build/python 513 300. Prints one line per (type, m): coverage identified / given, the
median EDF printed, and the types read."""
import sys

if any(a.startswith("-") for a in sys.argv[1:]):
    print(__doc__)
    sys.exit(0 if sys.argv[1:] in (["-h"], ["--help"]) else 2)
try:
    N = int(float(sys.argv[2])) if len(sys.argv) > 2 else 513
    RECORDS = int(sys.argv[3]) if len(sys.argv) > 3 else 300
except ValueError:
    sys.exit("theo1_coverage.py: N and RECORDS are numbers (--help)")
if N < 64 or RECORDS < 2:
    sys.exit("theo1_coverage.py: N is at least 64 and RECORDS at least 2 (--help)")
sys.path.insert(0, sys.argv[1] if len(sys.argv) > 1 else "build/python")
import numpy as np  # noqa: E402

import gyroflip  # noqa: E402
from gyroflip.allantools import Noise  # noqa: E402

TYPES = {2: "white PM", 1: "flicker PM", 0: "white FM", -1: "flicker FM", -2: "random-walk FM"}


def record(alpha, rng):
    """N phase points of the power-law type alpha (S_y ~ f^alpha, so S_x ~ f^(alpha - 2))."""
    if alpha == 2:
        return rng.standard_normal(N)
    if alpha == 0:
        return np.cumsum(rng.standard_normal(N))
    if alpha == -2:
        return np.cumsum(np.cumsum(rng.standard_normal(N)))
    noise = Noise(N, 1.0, alpha - 2)
    noise.generateNoise()
    return np.asarray(noise.time_series)[:N]


def main():
    top = N - 1 if (N - 1) % 2 == 0 else N - 2
    factors = [m for m in (16, 24, 48, 96, 192, 384, 500, 1000, 2000, 4000, 6000, top)
               if m <= top and (N - 1) // m + 1 < 30]
    taus = np.array(sorted(set(factors)), dtype=float)  # m tau0, as allantools' theo1 takes them
    rng = np.random.default_rng(11)
    np.random.seed(11)  # Kasdin's generator draws from NumPy's global generator
    for alpha, name in TYPES.items():
        dev, ok, ok_given, edf, read = [], [], [], [], []
        for _ in range(RECORDS):
            x = record(alpha, rng)
            d = gyroflip.deviation(x, kind="theo1", rate=1.0, input="angle", taus=taus)
            g = gyroflip.deviation(x, kind="theo1", rate=1.0, input="angle", taus=taus, alpha=alpha)
            dev.append(d.dev)
            ok.append((d.ci_lo, d.ci_hi))
            ok_given.append((g.ci_lo, g.ci_hi))
            edf.append(d.edf)
            read.append(d.alpha)
        dev, ok, ok_given = np.array(dev), np.array(ok), np.array(ok_given)
        truth = np.sqrt((dev**2).mean(axis=0))
        held = ((ok[:, 0] <= truth) & (truth <= ok[:, 1])).mean(axis=0)
        held_given = ((ok_given[:, 0] <= truth) & (truth <= ok_given[:, 1])).mean(axis=0)
        edf, read = np.array(edf), np.array(read)
        for j, m in enumerate(d.m):
            kinds, counts = np.unique(read[:, j], return_counts=True)
            types = ", ".join(f"{k:.0f}: {c}" for k, c in zip(kinds.tolist(), counts.tolist()))
            print(f"N {N} {name:15s} m {m:5d}  coverage {held[j]:.2f} (given type {held_given[j]:.2f})"
                  f"  median EDF {np.median(edf[:, j]):8.1f}  read {{{types}}}")


if __name__ == "__main__":
    main()
