#!/usr/bin/env python3
"""`gyroflip record` against `gyroflip emulate` over many seeds, each recording compared with
the emulator's log of what the device sent (bench/rig_truth.py; docs/RELIABILITY.md).

    python3 bench/record_figures.py [--gyroflip PATH] [--seeds FIRST-LAST] [--duration S]
        [--emulate "ARGS"] [--record "ARGS"] FAULTS...

Each FAULTS is a string of emulator fault options (e.g. "--fault-ber 2e-2"); each seed runs once
per FAULTS, one emulator and one recorder at a time (a recorder waiting for /dev/pts/N could
adopt the next emulator on that path). Prints one line per run and a total per FAULTS; exit 1
when any run mislabelled a dwell, exported one the device never sent, or lost one that no GAP
counts.

The issue-32 figure (docs/RELIABILITY.md): a reset 1.2 device seconds after the first START, on
a line that damages START's ACK often enough that a retry meets the rebooted device:

    python3 bench/record_figures.py --seeds 1000-1019 --duration 120 \\
        --emulate "--speed 50 --fault-reset-at 1.2" "--fault-ber 2e-2" "--fault-drop 1e-2"
"""
import argparse
import os
import shlex
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rig_truth  # noqa: E402


def one_run(gyroflip, seed, emulate_args, record_args, duration, folder):
    log = os.path.join(folder, "sent.csv")
    gfr = os.path.join(folder, "rec.gfr")
    emu = subprocess.Popen(
        [gyroflip, "emulate", "--pty", "--seed", str(seed), "--log", log] + emulate_args,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = emu.stdout.readline()
        pty = line.strip().split(" on ")[-1]
        if not pty.startswith("/"):
            raise SystemExit(f"emulate printed no line: {line!r} {emu.stderr.read()}")
        t0 = time.monotonic()
        rec = subprocess.run(
            [gyroflip, "record", "--port", pty, "--duration", str(duration), "-o", gfr] +
            record_args, capture_output=True, text=True, timeout=600)
        wall = time.monotonic() - t0
    finally:
        emu.send_signal(signal.SIGTERM)
        emu.wait(timeout=10)
    if not os.path.exists(gfr):
        return {"exit": rec.returncode, "error": rec.stderr.strip(), "wall_s": wall}
    r = rig_truth.compare(gyroflip, gfr, log)
    r["exit"] = rec.returncode
    r["wall_s"] = wall
    if rec.returncode != 0:
        r["error"] = rec.stderr.strip()
    return r


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--gyroflip", default=os.path.join(os.path.dirname(__file__), "..", "build",
                                                       "apps", "gyroflip", "gyroflip"))
    ap.add_argument("--seeds", default="1000-1019", help="FIRST-LAST (inclusive)")
    ap.add_argument("--duration", type=float, default=120)
    ap.add_argument("--emulate", default="--speed 50", help="emulator options of every run")
    ap.add_argument("--record", default="", help="recorder options of every run")
    ap.add_argument("faults", nargs="+", help="emulator fault options, one string per set")
    a = ap.parse_args()
    first, _, last = a.seeds.partition("-")
    seeds = range(int(first), int(last or first) + 1)
    bad = False
    for faults in a.faults:
        total = {"runs": 0, "sent": 0, "in_file": 0, "exported": 0, "mislabelled": 0,
                 "unlabelled": 0, "not_in_file": 0, "resets": 0, "start_unacked": 0,
                 "uncounted_runs": 0, "failed_runs": 0}
        for seed in seeds:
            with tempfile.TemporaryDirectory(prefix="gyroflip-figures-") as d:
                r = one_run(a.gyroflip, seed, shlex.split(a.emulate) + shlex.split(faults),
                            shlex.split(a.record), a.duration, d)
            print(f"{faults} seed {seed}: {r}", flush=True)
            total["runs"] += 1
            if "sent" not in r:
                total["failed_runs"] += 1
                bad = True
                continue
            for k in ("sent", "in_file", "exported", "mislabelled", "unlabelled", "not_in_file",
                      "resets", "start_unacked"):
                total[k] += r[k]
            total["uncounted_runs"] += 0 if r["counted"] else 1
            total["failed_runs"] += 1 if r["exit"] != 0 else 0
            bad = bad or r["mislabelled"] != 0 or r["foreign"] != 0 or not r["counted"]
        print(f"TOTAL {a.emulate} {faults}: {total}", flush=True)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
