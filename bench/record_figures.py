#!/usr/bin/env python3
"""`gyroflip record` against `gyroflip emulate` over many seeds, each recording compared with
the emulator's log of what the device sent (bench/rig_truth.py; docs/RELIABILITY.md).

    python3 bench/record_figures.py [--gyroflip PATH] [--seeds FIRST-LAST] [--duration S]
        [--emulate "ARGS"] [--record "ARGS"] [--reset-at LO-HI] [--fsize LO-HI] [--keep DIR]
        FAULTS...

Each FAULTS is a string of emulator fault options (e.g. "--fault-ber 2e-2"); each seed runs once
per FAULTS, one emulator and one recorder at a time (a recorder waiting for /dev/pts/N could
adopt the next emulator on that path). Prints one line per run and a total per FAULTS; exit 1
when any run mislabelled a dwell, exported one the device never sent or one twice, gave a time_s
that does not follow the device's clock within its run, or lost one that no GAP counts (boots
paired with the file's segments by INFO's boot count). The folder of every such run (rec.gfr, the emulator's sent.csv, both programs' stderr
and the commands) is kept in DIR (--keep, default ./record-figures-kept/FAULTS-INDEX/SEED-N),
never deleted: a rare failure is worth its evidence. `--reset-at LO-HI` gives each seed its own
`--fault-reset-at`, drawn uniformly in [LO, HI] from the seed (the same seed, the same time).
`--fsize LO-HI` records under `prlimit --fsize=N` (a full disk), N drawn the same way: such a run
must end with exit 1, a STOP record of reason 6 (disk full) and no torn record, and every dwell
in the file or counted (docs/RECORDER.md, "Disk full"):

    python3 bench/record_figures.py --seeds 5100-5119 --duration 600 --fsize 20000-60000 \
        --emulate "--speed max" "" "--fault-ber 1e-2" "--fault-reset-at 20 --fault-ber 1e-3"

The issue-32 figure (docs/RELIABILITY.md): a reset 1.2 device seconds after the first START, on
a line that damages START's ACK often enough that a retry meets the rebooted device:

    python3 bench/record_figures.py --seeds 1000-1019 --duration 120 \\
        --emulate "--speed 50 --fault-reset-at 1.2" "--fault-ber 2e-2" "--fault-drop 1e-2"
"""
import argparse
import os
import random
import shutil
import shlex
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rig_truth  # noqa: E402


def one_run(gyroflip, seed, emulate_args, record_args, duration, folder, fsize=None):
    log = os.path.join(folder, "sent.csv")
    gfr = os.path.join(folder, "rec.gfr")
    emu_cmd = [gyroflip, "emulate", "--pty", "--seed", str(seed), "--log", log] + emulate_args
    emu_err = open(os.path.join(folder, "emulate.stderr"), "w")
    emu = subprocess.Popen(emu_cmd, stdout=subprocess.PIPE, stderr=emu_err, text=True)
    try:
        line = emu.stdout.readline()
        pty = line.strip().split(" on ")[-1]
        if not pty.startswith("/"):
            raise SystemExit(f"emulate printed no line: {line!r}")
        rec_cmd = [gyroflip, "record", "--port", pty, "--duration", str(duration), "-o", gfr] + \
            record_args
        if fsize is not None:
            rec_cmd = ["prlimit", f"--fsize={fsize}"] + rec_cmd
        with open(os.path.join(folder, "commands.txt"), "w") as f:
            f.write(shlex.join(emu_cmd) + "\n" + shlex.join(rec_cmd) + "\n")
        t0 = time.monotonic()
        rec = subprocess.run(rec_cmd, capture_output=True, text=True, timeout=600)
        wall = time.monotonic() - t0
        with open(os.path.join(folder, "record.stderr"), "w") as f:
            f.write(rec.stderr)
    finally:
        emu.send_signal(signal.SIGTERM)
        emu.wait(timeout=10)
        emu_err.close()
    if not os.path.exists(gfr):
        return {"exit": rec.returncode, "error": rec.stderr.strip(), "wall_s": wall}
    r = rig_truth.compare(gyroflip, gfr, log)
    said = rec.stderr.rpartition(" over ")[2].split(" s")[0]  # "... over 60.6 s: ..."
    r["said_s"] = float(said) if said.replace(".", "", 1).isdigit() else None
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
    ap.add_argument("--reset-at", default="",
                    help="LO-HI: each seed's own --fault-reset-at, uniform in [LO, HI] by seed")
    ap.add_argument("--fsize", default="",
                    help="LO-HI: record under prlimit --fsize=N, N uniform in [LO, HI] by seed")
    ap.add_argument("--keep", default="record-figures-kept",
                    help="folder where the runs that failed a check are kept")
    ap.add_argument("faults", nargs="+", help="emulator fault options, one string per set")
    a = ap.parse_args()
    first, _, last = a.seeds.partition("-")
    seeds = range(int(first), int(last or first) + 1)
    bad = False
    for index, faults in enumerate(a.faults):
        total = {"runs": 0, "sent": 0, "in_file": 0, "exported": 0, "mislabelled": 0,
                 "unlabelled": 0, "not_in_file": 0, "resets": 0, "start_unacked": 0,
                 "uncounted_runs": 0, "failed_runs": 0, "over_10pct": 0, "max_data_ratio": 0.0,
                 "said_off": 0, "duplicates": 0, "time_inconsistent": 0, "disk_full_ends": 0}
        for seed in seeds:
            extra = []
            if a.reset_at:
                lo, _, hi = a.reset_at.partition("-")
                t = random.Random(seed).uniform(float(lo), float(hi or lo))
                extra = ["--fault-reset-at", f"{t:.4f}"]
            fsize = None
            if a.fsize:
                lo, _, hi = a.fsize.partition("-")
                fsize = random.Random(seed).randint(int(lo), int(hi or lo))
            d = tempfile.mkdtemp(prefix="gyroflip-figures-")
            try:
                r = one_run(a.gyroflip, seed, shlex.split(a.emulate) + shlex.split(faults) + extra,
                            shlex.split(a.record), a.duration, d, fsize)
                if fsize is not None:
                    r["fsize"] = fsize
            except Exception as e:  # noqa: BLE001 (kept with its folder)
                r = {"error": repr(e)}
            print(f"{faults} {' '.join(extra)} seed {seed}: {r}", flush=True)
            failed = "sent" not in r or r["mislabelled"] != 0 or r["foreign"] != 0 or \
                not r["counted"] or r["duplicates"] != 0 or r["time_inconsistent"] != 0
            # A full disk ends the run with exit 1, STOP (disk full) and no torn record.
            disk_full_end = "sent" in r and r["exit"] == 1 and r["stop"] == 6 and r["torn"] == 0
            failed = failed or (fsize is not None and not disk_full_end)
            if failed:
                kept = os.path.join(a.keep, f"{index}", f"{seed}")
                n = 0
                while os.path.exists(f"{kept}-{n}"):
                    n += 1
                os.makedirs(os.path.dirname(kept), exist_ok=True)
                shutil.move(d, f"{kept}-{n}")
                print(f"  kept in {kept}-{n}", flush=True)
            else:
                shutil.rmtree(d)
            total["runs"] += 1
            if "sent" not in r:
                total["failed_runs"] += 1
                bad = True
                continue
            for k in ("sent", "in_file", "exported", "mislabelled", "unlabelled", "not_in_file",
                      "resets", "start_unacked", "duplicates", "time_inconsistent"):
                total[k] += r[k]
            total["uncounted_runs"] += 0 if r["counted"] else 1
            ratio = r["data_s"] / a.duration
            total["over_10pct"] += 1 if ratio > 1.1 else 0
            total["max_data_ratio"] = round(max(total["max_data_ratio"], ratio), 3)
            # what record said against what the file holds (to its printed 0.1 s)
            total["said_off"] += 0 if r["said_s"] is not None and \
                abs(r["said_s"] - r["data_s"]) <= 0.05 else 1
            total["disk_full_ends"] += 1 if disk_full_end else 0
            total["failed_runs"] += 1 if r["exit"] != 0 and not disk_full_end else 0
            bad = bad or failed
        print(f"TOTAL {a.emulate} {faults}: {total}", flush=True)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
