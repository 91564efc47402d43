#!/usr/bin/env python3
"""Issue 23, section 4: every deviation of `gyroflip.allantools` beside allantools' own, in the
same process on the same array (data_type="freq", taus="octave"), best of REPEAT calls; and the
per-call overhead (a 1000-sample call). allantools is timed only when it can be imported
(PYTHONPATH); gyroflip never imports it otherwise. gcodev gets a second array of its own (two series
of one length), the same for both.

Usage: /usr/bin/python3 bench/python_vs_allantools.py [build/python] [sizes...] [--kinds=a,b,...]
       [--repeat=N]
Prints one line per (kind, N): gyroflip wall and CPU ms (CPU of all threads), allantools wall and
CPU ms (or "-"), the wall-time and CPU-time ratios (on a loaded machine the CPU ratio is the steadier
one: gyroflip's threads then wait for a core). docs/PERFORMANCE.md."""
import os
import sys
import time

REPEAT = 5


def best(f):
    """(wall, cpu) seconds of the fastest of REPEAT calls (cpu: all threads of the process)."""
    t = []
    for _ in range(REPEAT):
        c0, start = time.process_time(), time.perf_counter()
        f()
        t.append((time.perf_counter() - start, time.process_time() - c0))
    return min(t)


def call(module, kind, y, y2):
    """module.kind on the array(s), data_type="freq", taus="octave"."""
    f = getattr(module, kind)
    series = (y, y2) if kind == "gcodev" else (y,)
    return f(*series, data_type="freq", taus="octave")


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("-")]
    global REPEAT
    known = ["adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "mtotdev", "ttotdev",
             "htotdev", "theo1", "pdev", "mtie", "tierms", "gcodev", "gradev"]
    kinds = known
    for a in sys.argv[1:]:
        if a.startswith("--kinds="):
            kinds = a.split("=", 1)[1].split(",")
            if not set(kinds) <= set(known):
                sys.exit(f"python_vs_allantools.py: --kinds takes some of {','.join(known)}")
        elif a.startswith("--repeat="):
            value = a.split("=", 1)[1]
            if not value.isdigit() or int(value) < 1:
                sys.exit("python_vs_allantools.py: --repeat takes a whole number >= 1")
            REPEAT = int(value)
        elif a in ("-h", "--help"):
            print(__doc__)
            return
        elif a.startswith("-"):
            sys.exit(f"python_vs_allantools.py: unknown option {a} (--help)")
    pydir = args[0] if args else os.path.join(os.path.dirname(__file__), "..", "build", "python")
    try:
        sizes = [int(float(s)) for s in args[1:]] or [10 ** 6, 10 ** 7]
    except ValueError:
        sys.exit("python_vs_allantools.py: sizes are numbers such as 1e6 (--help)")
    if any(n < 1000 for n in sizes):
        sys.exit("python_vs_allantools.py: sizes are at least 1000 samples")
    sys.path.insert(0, pydir)
    import numpy as np
    import gyroflip.allantools as ours
    try:
        import allantools as theirs  # only when PYTHONPATH has it (never installed by gyroflip)
    except ImportError:
        theirs = None
    small = np.random.default_rng(2).normal(size=1000)
    small2 = np.random.default_rng(4).normal(size=1000)
    for k in kinds:
        t, _ = best(lambda: call(ours, k, small, small2))
        print(f"overhead {k:8s} N=1e3   gyroflip {t * 1e3:8.3f} ms", flush=True)
    for n in sizes:
        y = np.random.default_rng(1).normal(size=n)
        y2 = np.random.default_rng(3).normal(size=n)
        for k in kinds:
            g, g_cpu = best(lambda: call(ours, k, y, y2))
            a = None
            if theirs is not None and hasattr(theirs, k):
                a, a_cpu = best(lambda: call(theirs, k, y, y2))
            ratio = f"{a / g:6.1f}x (cpu {a_cpu / g_cpu:5.1f}x)" if a else "     -"
            at = f"{a * 1e3:9.2f} ms (cpu {a_cpu * 1e3:9.2f} ms)" if a else "        - "
            print(f"{k:8s} N={n:.0e}  gyroflip {g * 1e3:8.2f} ms (cpu {g_cpu * 1e3:8.2f} ms)  "
                  f"allantools {at}  {ratio}", flush=True)


if __name__ == "__main__":
    main()
