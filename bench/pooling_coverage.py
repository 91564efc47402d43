#!/usr/bin/env python3
"""Coverage of a calibration's stated uncertainty on the simulator (issue 31, docs/METHOD-NOTES.md
"Pooling runs"): campaigns of K stationary runs of one sensor at one temperature, each run a new
power-up (its g-term drawn from the preset's turn-on spread), calibrated together as `gyroflip
calibrate` does (random effects). Two truths are known:
  - the sensor's mean dN (the same runs with no turn-on spread): the calibrated value's 68.3 %
    interval (uncertainty.calibrated_dps) should hold it in ~68 % of campaigns;
  - the dN of the next power-up (one more run's drawn truth): the new power-up's 68.3 % interval
    (uncertainty.new_power_up_dps), what a compensated rate carries, likewise.
Also the weighted fit of before issue 31 (within-run weights, Birge-scaled error) for comparison.

With --no-spread every run is drawn from the preset without its turn-on spreads (the fourth
review of issue 31's tiny.toml): all power-ups share the mean dN, the case where the runs agree
within their own noise and the untruncated Knapp-Hartung error fell below it (F1).

Usage: python3 bench/pooling_coverage.py [BUILD/python] [--campaigns=N] [--runs=2,3,5,8]
       [--sensor=hz1-90-100a] [--duration=900] [--no-spread]
Prints one row per K: coverage of each interval with its binomial standard error."""
import json
import math
import os
import sys
import tempfile

import numpy as np


def parse(argv):
    opts = {"campaigns": 200, "runs": [2, 3, 5, 8], "sensor": "hz1-90-100a", "duration": 900.0,
            "no_spread": False}
    pydir = os.path.join(os.path.dirname(__file__), "..", "build", "python")
    for a in argv:
        if a in ("-h", "--help"):
            print(__doc__)
            sys.exit(0)
        if a.startswith("--campaigns="):
            opts["campaigns"] = int(a.split("=", 1)[1])
        elif a.startswith("--runs="):
            opts["runs"] = [int(x) for x in a.split("=", 1)[1].split(",")]
        elif a.startswith("--sensor="):
            opts["sensor"] = a.split("=", 1)[1]
        elif a.startswith("--duration="):
            opts["duration"] = float(a.split("=", 1)[1])
        elif a == "--no-spread":
            opts["no_spread"] = True
        elif a.startswith("-"):
            sys.exit(f"pooling_coverage.py: unknown option {a} (--help)")
        else:
            pydir = a
    return pydir, opts


def write_csv(path, rec, sensor):
    """A recording CSV (docs/FORMATS.md) of a simulated run's arrays."""
    with open(path, "w") as f:
        f.write(f"# sensor_name: {sensor}\n# temp_c: 20\ntime_s,angle_deg,rate_dps,temp_c,n_avg\n")
        for t, a, r, c, n in zip(rec["time_s"], rec["angle_deg"], rec["rate_dps"], rec["temp_c"],
                                 rec["n_avg"]):
            f.write(f"{t!r},{'' if math.isnan(a) else repr(a)},{r!r},{c!r},{int(n)}\n")


def main():
    pydir, o = parse(sys.argv[1:])
    sys.path.insert(0, pydir)
    import gyroflip
    tmp = tempfile.mkdtemp(prefix="pooling_coverage.")
    # The sensor's mean dN: the preset without its turn-on spread (the mean g-term).
    still = os.path.join(tmp, "still.toml")
    with open(still, "w") as f:
        f.write(f'base = "{o["sensor"]}"\nname = "mean"\ng_sens_turn_on_sigma_dps_per_g = 0.0\n'
                'g_sens_tc_turn_on_sigma_dps_per_g_c = 0.0\n')
    mean_truth = gyroflip.simulate(still, duration_s=10.0, seed=1, temp=20)["delta_n_truth_dps"]
    runs_from = still if o["no_spread"] else o["sensor"]
    print(f"sensor {o['sensor']}{' without turn-on spreads' if o['no_spread'] else ''}, runs of "
          f"{o['duration']:g} s at 20 degC, {o['campaigns']} campaigns per K; mean dN "
          f"{mean_truth:.6g} deg/s")
    print("K  calibrated(RE)  new-power-up(RE)  calibrated(weighted, before)")
    seed = 1000
    for k in o["runs"]:
        hit_cal = hit_new = hit_old = 0
        for c in range(o["campaigns"]):
            files = []
            for i in range(k):
                seed += 1
                rec = gyroflip.simulate(runs_from, duration_s=o["duration"], seed=seed, temp=20)
                files.append(os.path.join(tmp, f"run{i}.csv"))
                write_csv(files[-1], rec, "mean" if o["no_spread"] else o["sensor"])
            seed += 1
            new_truth = gyroflip.simulate(runs_from, duration_s=10.0, seed=seed,
                                          temp=20)["delta_n_truth_dps"]
            cal = gyroflip.calibrate_runs(files)
            m, u = cal["model"], cal["uncertainty"]
            hit_cal += abs(m["coeffs_dps"][0] - mean_truth) <= u["calibrated_dps"]
            hit_new += abs(m["coeffs_dps"][0] - new_truth) <= u["new_power_up_dps"]
            # Before: weights 1/se^2, error scaled by the Birge ratio.
            dn = np.array([f["delta_n_dps"] for f in cal["files"]])
            se = np.array([f["stderr_correlated_dps"] for f in cal["files"]])
            w = 1 / se ** 2
            wm = (w * dn).sum() / w.sum()
            chi = (w * (dn - wm) ** 2).sum() / (k - 1)
            hit_old += abs(wm - mean_truth) <= math.sqrt(max(1.0, chi) / w.sum())
        n = o["campaigns"]

        def cov(h):
            p = h / n
            return f"{p:.3f} ± {math.sqrt(p * (1 - p) / n):.3f}"
        print(f"{k}  {cov(hit_cal):14s}  {cov(hit_new):16s}  {cov(hit_old)}", flush=True)


if __name__ == "__main__":
    main()
