#!/usr/bin/env python3
"""Coverage of the pooled dN's 68.3 % interval on synthetic runs (docs/METHOD-NOTES.md, "Pooling
runs"; fourth review of issue 31, F1): K runs at one temperature, dN_i = mu + u_i + e_i with
u_i ~ N(0, tau^2) and e_i ~ N(0, se_i^2), se_i uniform in 0.5-1.5 units, pooled as
method::fit_delta_n_random_effects pools them (DerSimonian-Laird tau^2, weights 1/(se^2 + tau^2),
Knapp-Hartung scale q, Student's t for K - 1 degrees of freedom): the share of campaigns whose
interval holds mu, with the untruncated q (before) and the modified q* = max(1, q) (Roever,
Knapp & Friede 2015), and how often the untruncated error fell below the fixed-effect error.

Usage: python3 bench/pooling_synthetic_coverage.py [--campaigns=N] [--seed=S]"""
import math
import sys

import numpy as np


def t_one_sigma(nu):
    """Student's t quantile at 0.8413 (the 68.3 % two-sided interval) for nu degrees of freedom,
    by bisection of the density's integral (Simpson; no SciPy needed)."""
    c = math.gamma((nu + 1) / 2) / (math.sqrt(nu * math.pi) * math.gamma(nu / 2))

    def half_mass(x):  # integral of the density from 0 to x
        xs = np.linspace(0.0, x, 20001)
        f = c * (1 + xs ** 2 / nu) ** (-(nu + 1) / 2)
        h = x / 20000
        return h / 3 * (f[0] + f[-1] + 4 * f[1:-1:2].sum() + 2 * f[2:-1:2].sum())

    lo, hi = 0.0, 10.0
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if half_mass(mid) < 0.6826894921370859 / 2 else (lo, mid)
    return (lo + hi) / 2


def main():
    campaigns, seed = 4000, 31
    for a in sys.argv[1:]:
        if a.startswith("--campaigns="):
            campaigns = int(a.split("=", 1)[1])
        elif a.startswith("--seed="):
            seed = int(a.split("=", 1)[1])
        else:
            sys.exit(__doc__)
    rng = np.random.default_rng(seed)
    print("K  tau  coverage(q, before)  coverage(max(1,q))  share below fixed-effect (before)")
    for k in (2, 3, 5, 13):
        t = t_one_sigma(k - 1)
        for tau in (0.0, 0.5, 1.0, 3.0, 10.0):
            se = rng.uniform(0.5, 1.5, (campaigns, k))
            y = tau * rng.standard_normal((campaigns, k)) + se * rng.standard_normal((campaigns, k))
            w = 1 / se ** 2
            mfe = (w * y).sum(1) / w.sum(1)
            qstat = (w * (y - mfe[:, None]) ** 2).sum(1)
            tau2 = np.maximum(0, (qstat - (k - 1)) / (w.sum(1) - (w ** 2).sum(1) / w.sum(1)))
            ws = 1 / (se ** 2 + tau2[:, None])
            m = (ws * y).sum(1) / ws.sum(1)
            q = (ws * (y - m[:, None]) ** 2).sum(1) / (k - 1)
            se_kh = np.sqrt(q / ws.sum(1))
            se_mod = np.sqrt(np.maximum(1, q) / ws.sum(1))
            below = (se_kh < 1 / np.sqrt(w.sum(1))).mean()
            print(f"{k:2d} {tau:4g}  {(np.abs(m) <= t * se_kh).mean():.3f}"
                  f"                {(np.abs(m) <= t * se_mod).mean():.3f}"
                  f"               {below:.3f}", flush=True)


if __name__ == "__main__":
    main()
