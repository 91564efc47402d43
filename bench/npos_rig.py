#!/usr/bin/env python3
"""N positions on the rig, end to end (issue 33 item 2): `gyroflip emulate --azimuth A --truth`,
`gyroflip record --positions P` and `gyroflip calibrate --pairing harmonic --json` over many
seeds; each term's error over its reported 1 sigma against the emulator's truth (c1, s1; c2 and
s2 are 0). Prints one line per seed and, per term, the mean and standard deviation of z = (value
- truth) / sigma and the share of |z| <= 1 (a Gaussian: 0, 1 and 68.3 %).

    python3 bench/npos_rig.py [--gyroflip PATH] [--seeds FIRST-LAST] [--duration S]
        [--positions A,B,...] [--azimuth DEG] [--emulate "ARGS"] [--record "ARGS"]

One emulator and one recorder at a time (a recorder waiting for /dev/pts/N could adopt the next
emulator on that path); each emulator is stopped (SIGTERM, by its own PID) before the next.
"""
import argparse
import json
import math
import os
import shlex
import signal
import subprocess
import sys
import tempfile
import time


def run_seed(exe, seed, args, folder):
    truth = os.path.join(folder, f"truth{seed}.json")
    gfr = os.path.join(folder, f"run{seed}.gfr")
    emu = subprocess.Popen([exe, "emulate", "--pty", "--speed", "max", "--seed", str(seed),
                            "--azimuth", str(args.azimuth), "--truth", truth]
                           + shlex.split(args.emulate),
                           stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        line = emu.stdout.readline()
        if "the rig is on " not in line:
            raise RuntimeError(f"seed {seed}: emulate said {line!r}")
        pty = line.strip().split("the rig is on ")[1]
        rec = subprocess.run([exe, "record", "--port", pty, "--duration", str(args.duration),
                              "--positions", args.positions, "-o", gfr]
                             + shlex.split(args.record), capture_output=True, text=True)
        if rec.returncode != 0:
            raise RuntimeError(f"seed {seed}: record: {rec.stderr}")
    finally:
        os.kill(emu.pid, signal.SIGTERM)
        emu.wait()
    cal = subprocess.run([exe, "calibrate", gfr, "--pairing", "harmonic", "--json"],
                         capture_output=True, text=True)
    if cal.returncode != 0:
        raise RuntimeError(f"seed {seed}: calibrate: {cal.stderr}")
    j = json.loads(cal.stdout)
    with open(truth, encoding="utf-8") as f:
        t = json.load(f)
    out = {}
    for term in j["terms"]:
        name = term["name"]
        if name == "b":
            continue
        value, se = term["value_dps"], term["stderr_correlated_dps"]
        out[name] = ((value - t[f"{name}_dps"]) / se, value, t[f"{name}_dps"], se)
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--gyroflip", default="build/apps/gyroflip/gyroflip")
    p.add_argument("--seeds", default="1-20")
    p.add_argument("--duration", type=float, default=600.0)
    p.add_argument("--positions", default="0,90,180,270")
    p.add_argument("--azimuth", type=float, default=30.0)
    p.add_argument("--emulate", default="")
    p.add_argument("--record", default="")
    args = p.parse_args()
    first, last = (int(x) for x in args.seeds.split("-"))
    zs = {}
    start = time.time()
    with tempfile.TemporaryDirectory() as folder:
        for seed in range(first, last + 1):
            r = run_seed(args.gyroflip, seed, args, folder)
            print(f"seed {seed}: " + "  ".join(
                f"{k} {v[1]:+.6f} truth {v[2]:+.6f} sigma {v[3]:.6f} z {v[0]:+.2f}"
                for k, v in r.items()), flush=True)
            for k, v in r.items():
                zs.setdefault(k, []).append(v[0])
    for k, z in zs.items():
        n = len(z)
        mean = sum(z) / n
        sd = math.sqrt(sum((x - mean) ** 2 for x in z) / (n - 1)) if n > 1 else float("nan")
        inside = sum(1 for x in z if abs(x) <= 1.0) / n
        print(f"{k}: {n} runs, z mean {mean:+.2f}, z sd {sd:.2f}, |z| <= 1 in {100 * inside:.0f} %")
    print(f"{time.time() - start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
