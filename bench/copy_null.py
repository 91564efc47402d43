#!/usr/bin/env python3
"""Copies of a calibration run found by content (fifth review of issue 31, F5;
method/cycle_print.hpp): false copies among independent runs, and copies found.

Per sensor (hz1-90-100a, adxrs150) and pairing (abba, simple): RUNS runs (seeds 1..RUNS, 600 s,
20 degC) are calibrated together (`gyroflip calibrate`, each run's cycle print in the file); RUNS
other runs (seeds 1001..) are compensated with that calibration (`gyroflip compensate
--calibration`), each against every run's print: RUNS x RUNS independent pairs, a false copy being
any "as the calibration's run" warning; calibrate itself compares its RUNS (RUNS(RUNS-1)/2 pairs,
"the same data twice") and says whether its lower-tail test (runs agreeing far below their
errors) fired. Then each calibration run's copies: rate_dps rounded to
1e-4 and 1e-3 deg/s, time shifted by 1 h, trimmed (rows 37 to the last 20), its second half: a
copy found when compensate names the run.

Usage: python3 bench/copy_null.py [GYROFLIP_EXE] [--runs N]"""
import argparse
import os
import subprocess
import sys
import tempfile


def sh(exe, *args):
    r = subprocess.run([exe, *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(args)}: exit {r.returncode}: {r.stderr}")
    return r.stderr


def rewrite(src, dst, first=0, drop_last=0, shift_s=0.0, digits=None, half=False):
    head, rows = [], []
    with open(src) as f:
        for line in f:
            (head if line.startswith("#") or not rows and line.startswith("time_s") else rows
             ).append(line)
    if half:
        first = len(rows) // 2
    rows = rows[first:len(rows) - drop_last]
    out = []
    for line in rows:
        c = line.rstrip("\n").split(",")
        if shift_s:
            c[0] = repr(float(c[0]) + shift_s)
        if digits is not None:
            c[2] = f"{float(c[2]):.{digits}f}"
        out.append(",".join(c) + "\n")
    with open(dst, "w") as f:
        f.writelines(head + out)


COPIES = [("rounded 1e-4", dict(digits=4)), ("rounded 1e-3", dict(digits=3)),
          ("shifted 1 h", dict(shift_s=3600.0)), ("trimmed", dict(first=37, drop_last=20)),
          ("second half", dict(half=True))]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("exe", nargs="?", default=os.path.join(os.path.dirname(__file__), "..",
                                                           "build", "apps", "gyroflip",
                                                           "gyroflip"))
    ap.add_argument("--runs", type=int, default=15)
    o = ap.parse_args()
    n = o.runs
    print(f"{n} calibration runs x {n} independent runs per row; 600 s, 20 degC")
    print(f"{'sensor pairing':28s} false copies / pairs   " +
          "   ".join(f"{name} found" for name, _ in COPIES))
    with tempfile.TemporaryDirectory() as d:
        for sensor in ("hz1-90-100a", "adxrs150"):
            for pairing in ("abba", "simple"):
                def sim(seed):
                    f = os.path.join(d, f"{sensor}-{seed}.csv")
                    if not os.path.exists(f):
                        sh(o.exe, "simulate", "--sensor", sensor, "--duration", "600", "--temp",
                           "20", "--seed", str(seed), "-o", f)
                    return f
                cal_runs = [sim(s) for s in range(1, n + 1)]
                cal = os.path.join(d, "cal.json")
                err = sh(o.exe, "calibrate", *cal_runs, "--pairing", pairing, "-o", cal)
                # calibrate's own runs, pairwise (n(n-1)/2 independent pairs), and the lower tail
                false_cal = err.count("the same data twice")
                alike = "agree far better" in err
                false = 0
                for s in range(1001, 1001 + n):
                    err = sh(o.exe, "compensate", sim(s), "--calibration", cal, "-o",
                             os.path.join(d, "out.csv"))
                    false += err.count("as the calibration's run")
                found = []
                for name, kw in COPIES:
                    k = 0
                    for run in cal_runs:
                        copy = os.path.join(d, "copy.csv")
                        rewrite(run, copy, **kw)
                        err = sh(o.exe, "compensate", copy, "--calibration", cal, "-o",
                                 os.path.join(d, "out.csv"))
                        k += f"as the calibration's run {run}" in err
                    found.append(f"{k:>{len(name) + 3}d}/{n}")
                print(f"{sensor + ' ' + pairing:28s} {false:6d} / {n * n:<10d} " +
                      "".join(f"{x:>{len(name) + 9}s}" for x, (name, _) in zip(found, COPIES)) +
                      f"   calibrate: {false_cal} false copies of {n * (n - 1) // 2} pairs, "
                      f"lower tail {'WARNED' if alike else 'quiet'}", flush=True)


if __name__ == "__main__":
    main()
