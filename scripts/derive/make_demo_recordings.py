#!/usr/bin/env python3
"""Writes the two small demo recordings in tests/vectors/demo/ (standard library only).

Dwell-average rows as the paper's rig records them (256 conversions of 2 ms per dwell, a 0/180
cycle every 1.79 s), for an ADXRS150-like sensor on a table at 42.6 deg N with a north-pointing
sensitive axis:
  y = s*(w_in + W_E cos(lat) + d_g) + b(t) + noise,
  b(t) = 2.48 + 0.6*exp(-t/420) + 2e-6*t  (switched on at t = 0, paper Fig. 3),  d_g = 0.39 deg/s,
  noise: 0.05 deg/s per dwell (0.05 deg/s/rtHz averaged over 0.512 s), temperature 20 -> 21 degC.
Truth: dN = d_g + W_E cos(42.6 deg) = 0.39 + 0.0030754682 = 0.3930754682 deg/s.
Python's random (Mersenne Twister) with fixed seeds gives the same files on every platform.
"""
import math
import os
import random

W_E_DPS = 7.2921150e-5 * 180.0 / math.pi
LAT_DEG = 42.6
D_G = 0.39
DN = D_G + W_E_DPS * math.cos(math.radians(LAT_DEG))


def write(path, seed, n_cycles, input_dps, comment):
    rnd = random.Random(seed)
    with open(path, "w", newline="\n") as f:
        f.write(f"# {comment}\n")
        f.write("# sensor: adxrs150-like (synthetic, scripts/derive/make_demo_recordings.py)\n")
        f.write(f"# truth_delta_n_dps: {DN:.10f}\n# truth_input_dps: {input_dps}\n# lat_deg: {LAT_DEG}\n# axis: north\n")
        f.write("time_s,angle_deg,rate_dps,temp_c,n_avg\n")
        for k in range(2 * n_cycles):
            t = 0.256 + k * 0.895
            s = 1 if k % 2 == 0 else -1
            bias = 2.48 + 0.6 * math.exp(-t / 420.0) + 2e-6 * t
            temp = 20.0 + t / (2 * n_cycles * 0.895)
            y = s * (input_dps + DN) + bias + rnd.gauss(0.0, 0.05)
            f.write(f"{t:.3f},{0 if s > 0 else 180},{y:.6f},{temp:.2f},256\n")


here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "vectors", "demo")
write(os.path.join(here, "cal_stationary_20c.csv"), 1, 1000, 0.0, "stationary calibration run, 30 min")
write(os.path.join(here, "run_rate_table_20c.csv"), 2, 340, 0.25, "rate-table run at 0.25 deg/s, 10 min")
