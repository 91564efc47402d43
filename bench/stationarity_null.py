#!/usr/bin/env python3
"""The stationarity test (issue 31, method/stationarity.hpp) on the simulator: how often it calls a
stationary calibration run non-stationary (false alarms), and whether it catches the issue's
non-stationary runs (detections). Every run goes through gyroflip.calibrate, the library call
`gyroflip calibrate` makes, with the sensor's specification.

Stationary runs: both presets, cold (sensor just powered, warm-up drift) and warm (30 min on
before), abba and simple pairing, 600 s and 5400 s. Non-stationary: a constant input of 0.5 and
0.1 deg/s, a zero-mean sine of 0.5 deg/s over 500 s and of 0.02 deg/s, a step of 0.003 deg/s
halfway.

Usage: python3 bench/stationarity_null.py [BUILD/python] [--seeds=N] [--looks | --power]
Prints the share of runs failing, per case, with the statistics' largest values. With --looks,
the recorder's live test instead: each stationary run tested at the cycle counts `record` tests
it at (40, then 25 % more each time, method::next_stationarity_look, and at the end), a run
failing when any look fails. With --power, the drift and step statistics' power (fifth review of
issue 31, F1 and F2): 30-min HZ1-90-100A runs (abba, 20 degC, warm) with a step of the input at
3, 10, 50, 90 and 97 % of the run, and input ramps 0 -> 0.002 and 0 -> 0.003 deg/s (a staircase
of 60 steps), each with how far the input moves dN in the run's correlated errors. Run it with an
older build's python directory for the figures before."""
import argparse
import os
import sys


def parse(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("pydir", nargs="?",
                    default=os.path.join(os.path.dirname(__file__), "..", "build", "python"))
    ap.add_argument("--seeds", type=int, default=50)
    ap.add_argument("--looks", action="store_true")
    ap.add_argument("--power", action="store_true")
    o = ap.parse_args(argv)
    return o.pydir, o.seeds, o.looks, o.power


def looks_of(n_cycles):
    """The recorder's schedule (method::next_stationarity_look): 40, then 25 % more, and the end."""
    out, n = [], 40
    while n < n_cycles:
        out.append(n)
        n = max(n + 1, (n * 5 + 3) // 4)
    return out + [n_cycles]


def ratios(st):
    """Each statistic over its limit (scatter, drift, step, slope, noise, outlier): above 1 fails
    (drift, step and slope only with a level change beyond 3 correlated errors too)."""
    step = st["step_statistic"] / st["step_statistic_limit"] if st.get("step_statistic_limit") else 0
    slope = abs(st["slope_statistic"]) / st["slope_limit"] if st.get("slope_limit") else 0
    noise = st["noise"]["ratio"] / st["noise"]["limit"] if st.get("noise") else 0
    return [st["scatter_ratio"] / st["scatter_limit"], st["drift_statistic"] / st["drift_limit"],
            step, slope, noise, st["outlier_z"] / st["outlier_limit"]]


def run_looks(gyroflip, sensor, seed, duration, on_before):
    """Any of the recorder's looks at a growing abba run failing, and each statistic's largest
    ratio to its limit over the looks."""
    rec = gyroflip.simulate(sensor, duration_s=duration, seed=seed, temp=20, rate="0",
                            power_on_before_s=on_before)
    rows = len(rec["time_s"])
    worst = [0.0] * 6
    # abba: one cycle per two dwells (rows)
    for n in looks_of(rows // 2):
        k = 2 * n
        cal = gyroflip.calibrate(rec["time_s"][:k], rec["angle_deg"][:k], rec["rate_dps"][:k],
                                 rec["temp_c"][:k], rec["n_avg"][:k], latitude=42.6,
                                 axis="north", pairing="abba", sensor=sensor)
        st = cal["files"][0]["stationarity"]
        worst = [max(a, b) for a, b in zip(worst, ratios(st))]
        if not st["stationary"]:
            return True, n, worst
    return False, rows // 2, worst


def main_looks(gyroflip, seeds):
    print(f"{seeds} seeds per row; the recorder's looks; latitude 42.6, axis north, 20 degC")
    print(f"{'case':48s} looks  runs failing any look   largest statistic / limit over the "
          "looks: scatter drift step slope noise outlier")
    for sensor in ("hz1-90-100a", "adxrs150"):
        for on_before in (0.0, 1800.0):
            for duration in (1800.0, 14400.0):
                failed = 0
                worst = [0.0] * 6
                for seed in range(1, seeds + 1):
                    f, _, w = run_looks(gyroflip, sensor, seed, duration, on_before)
                    failed += f
                    worst = [max(a, b) for a, b in zip(worst, w)]
                n = len(looks_of(int(duration / 1.79)))
                name = (f"stationary {sensor} {'cold' if on_before == 0 else 'warm'} "
                        f"{duration:.0f} s")
                print(f"{name:48s} {n:5d}  {failed / seeds:.3f}                    " +
                      " ".join(f"{x:.2f}" for x in worst), flush=True)


def run(gyroflip, sensor, seed, duration, pairing, on_before, rate="0"):
    rec = gyroflip.simulate(sensor, duration_s=duration, seed=seed, temp=20, rate=rate,
                            power_on_before_s=on_before)
    cal = gyroflip.calibrate(rec["time_s"], rec["angle_deg"], rec["rate_dps"], rec["temp_c"],
                             rec["n_avg"], latitude=42.6, axis="north", pairing=pairing,
                             sensor=sensor)
    return cal["files"][0]["stationarity"]


def power_cases(duration=1800.0):
    """(name, rate profile, mean input over the run in deg/s) of the power study."""
    out = []
    for size in (0.01, 0.004):
        for share in (0.03, 0.10, 0.50, 0.90, 0.97):
            at = share * duration
            out.append((f"step {size:g} deg/s at {share * 100:.0f} % ({at:.0f} s)",
                        f"steps:0:0,{at:g}:{size:g}", size * (1.0 - share)))
    for rise in (0.002, 0.003):
        prof = "steps:" + ",".join(f"{i * 30:g}:{rise * i / 59:.6g}" for i in range(60))
        out.append((f"ramp 0 -> {rise:g} deg/s", prof, rise / 2.0))
    return out


def main_power(gyroflip, seeds):
    print(f"{seeds} seeds per row (1-{seeds}); hz1-90-100a, 1800 s, abba, warm, latitude 42.6, "
          "axis north, 20 degC")
    print(f"{'case':34s} caught   dN off (correlated errors)  drift / limit  step / limit  "
          "slope / limit")
    for name, prof, mean_in in power_cases():
        caught = 0
        offs, d, st_, sl = [], [], [], []
        for seed in range(1, seeds + 1):
            rec = gyroflip.simulate("hz1-90-100a", duration_s=1800.0, seed=seed, temp=20,
                                    rate=prof, power_on_before_s=1800.0)
            cal = gyroflip.calibrate(rec["time_s"], rec["angle_deg"], rec["rate_dps"],
                                     rec["temp_c"], rec["n_avg"], latitude=42.6, axis="north",
                                     pairing="abba", sensor="hz1-90-100a")
            st = cal["files"][0]["stationarity"]
            caught += not st["stationary"]
            offs.append(mean_in / cal["stderr_correlated_dps"])
            d.append(st["drift_statistic"] / st["drift_limit"])
            if st.get("step_statistic_limit"):
                st_.append(st["step_statistic"] / st["step_statistic_limit"])
                sl.append(abs(st["slope_statistic"]) / st["slope_limit"])

        def span(v):
            return f"{min(v):.2f}-{max(v):.2f}" if v else "-"
        print(f"{name:34s} {caught:2d}/{seeds:<4d} {span(offs):27s} {span(d):14s} "
              f"{span(st_):13s} {span(sl)}", flush=True)


def main():
    pydir, seeds, looks, power = parse(sys.argv[1:])
    sys.path.insert(0, pydir)
    import gyroflip
    if looks:
        return main_looks(gyroflip, seeds)
    if power:
        return main_power(gyroflip, seeds)
    print(f"{seeds} seeds per row; latitude 42.6, axis north, 20 degC")
    print(f"{'case':58s} failed   max scatter  max drift  max step  max slope  max noise  max outlier")
    cases = []
    for sensor in ("hz1-90-100a", "adxrs150"):
        for on_before in (0.0, 1800.0):
            for pairing in ("abba", "simple"):
                for duration in (600.0, 5400.0):
                    cases.append((f"stationary {sensor} {'cold' if on_before == 0 else 'warm'} "
                                  f"{pairing} {duration:.0f} s", sensor, duration, pairing,
                                  on_before, "0"))
    for rate in ("0.5", "0.1", "sine:0.5:0.002", "sine:0.02:0.002", "steps:0:0,900:0.003"):
        cases.append((f"input {rate} hz1-90-100a abba 1800 s", "hz1-90-100a", 1800.0, "abba",
                      1800.0, rate))
    for name, sensor, duration, pairing, on_before, rate in cases:
        failed = 0
        worst_s = worst_d = worst_t = worst_b = worst_n = worst_o = 0.0
        for seed in range(1, seeds + 1):
            st = run(gyroflip, sensor, seed, duration, pairing, on_before, rate)
            failed += not st["stationary"]
            worst_s = max(worst_s, st["scatter_ratio"] / st["scatter_limit"])
            worst_d = max(worst_d, st["drift_statistic"] / st["drift_limit"])
            if st.get("step_statistic_limit"):  # absent before the step and slope statistics
                worst_t = max(worst_t, st["step_statistic"] / st["step_statistic_limit"])
                worst_b = max(worst_b, abs(st["slope_statistic"]) / st["slope_limit"])
            worst_n = max(worst_n, st["noise"]["ratio"] if st.get("noise") else 0.0)
            worst_o = max(worst_o, st["outlier_z"] / st["outlier_limit"])
        print(f"{name:58s} {failed / seeds:6.3f}   {worst_s:10.3f}  {worst_d:9.3f}  "
              f"{worst_t:8.3f}  {worst_b:9.3f}  {worst_n:9.2f}  {worst_o:11.3f}", flush=True)
    print("(max scatter, drift, step, slope, outlier: the largest statistic over its limit; above 1 "
          "fails, the drift, step and slope only when the level change also exceeds 3 correlated "
          "errors; max noise: the largest std(r) over the specification's white noise for the "
          "dwells, limit 4)")


if __name__ == "__main__":
    main()
