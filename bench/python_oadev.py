#!/usr/bin/env python3
"""The figure issue 11 names: gyroflip.oadev in-process on 1e7 and 1e8 samples against a plain
NumPy implementation of the same statistic (cumsum + slicing, as allantools computes it), the
call alone (the data made before the clock starts) and the peak RSS of a process doing only that.

Usage (Debian's interpreter, after a build):
    /usr/bin/python3 bench/python_oadev.py [build/python] [sizes...]
Prints one line per (implementation, N): seconds and peak RSS in MB. Each measurement runs in a
fresh process so that its peak RSS is its own. Results in docs/PERFORMANCE.md."""
import os
import subprocess
import sys

CHILD = r'''
import resource, sys, time
sys.path.insert(0, sys.argv[1])
import numpy as np
impl, n = sys.argv[2], int(float(sys.argv[3]))
y = np.random.default_rng(1).normal(size=n)     # frequency (rate) data, 8 bytes a sample
if impl == "gyroflip":
    import gyroflip
    start = time.perf_counter()
    taus, devs, errs, ns = gyroflip.oadev(y, rate=1.0, data_type="freq", taus="octave")
else:
    start = time.perf_counter()
    # allantools: frequency2phase (mean removed, cumsum, a leading 0), octave taus, then per m
    # the phase sliced three ways and the second differences summed (calc_adev_phase, stride 1).
    phase = np.insert(np.cumsum(y - np.mean(y)), 0, 0.0)
    N = len(phase)
    devs = []
    for m in 2 ** np.arange(int(np.log2(N)) + 1):
        if N - 2 * m < 2:
            break
        d = phase[2 * m:] - 2 * phase[m:N - m] + phase[:N - 2 * m]
        devs.append(np.sqrt(np.sum(d * d) / (2.0 * len(d))) / m)
elapsed = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(f"{impl:9s} N={n:.0e}  {elapsed:7.2f} s  peak RSS {peak:6.0f} MB  (data {8 * n / 1e6:.0f} MB)  oadev(1)={devs[0]:.6f}")
'''


def main():
    pydir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "build", "python")
    sizes = sys.argv[2:] or ["1e7", "1e8"]
    for n in sizes:
        for impl in ("gyroflip", "numpy"):
            subprocess.run([sys.executable, "-c", CHILD, pydir, impl, n], check=True)


if __name__ == "__main__":
    main()
