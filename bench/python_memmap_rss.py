#!/usr/bin/env python3
"""Peak memory of gyroflip.deviation on a memory-mapped .npy file of N samples (issue 11: 1e9
samples in bounded memory). Writes the file (N x 8 bytes: 8 GB for 1e9) in a folder you give,
then in a fresh process loads it with mmap_mode="r", runs OADEV (octave taus, no bounds) and
prints the call's time, the process's peak RSS growth, and the result at tau0.

Usage: /usr/bin/python3 bench/python_memmap_rss.py build/python DIR [N=1e9] [KIND=oadev]
Figures in docs/python.md ("Arrays, memory")."""
import os
import subprocess
import sys

import numpy as np

CHILD = r'''
import resource, sys, time
sys.path.insert(0, sys.argv[1])
import numpy as np, gyroflip
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
y = np.load(sys.argv[2], mmap_mode="r")
start = time.perf_counter()
d = gyroflip.deviation(y, sys.argv[3], rate=100.0, ci=None)
elapsed = time.perf_counter() - start
grown = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base) / 1024
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(f"{sys.argv[3]} of {len(y):.0e} memory-mapped samples ({8 * len(y) / 1e9:.1f} GB): "
      f"{elapsed:.1f} s, peak RSS {peak:.0f} MB ({grown:.0f} MB above the interpreter's peak "
      f"before the call), dev(tau0) {d.dev[0]:.6f}, {len(d.dev)} taus")
'''


def main():
    pydir, folder = sys.argv[1], sys.argv[2]
    n = int(float(sys.argv[3])) if len(sys.argv) > 3 else 1_000_000_000
    kind = sys.argv[4] if len(sys.argv) > 4 else "oadev"
    path = os.path.join(folder, f"memmap_{n}.npy")
    if not os.path.exists(path):
        a = np.lib.format.open_memmap(path, mode="w+", dtype=np.float64, shape=(n,))
        rng = np.random.default_rng(1)
        step = 10_000_000
        for k in range(0, n, step):
            a[k:k + step] = rng.normal(size=min(step, n - k))
        a.flush()
        del a
    subprocess.run([sys.executable, "-c", CHILD, pydir, path, kind], check=True)


if __name__ == "__main__":
    main()
