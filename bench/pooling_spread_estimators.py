#!/usr/bin/env python3
"""Estimators of a between-run variance that changes with temperature, tau^2(T) = t0 + t1 x^2
(x = T - T_ref), compared on synthetic campaigns (docs/METHOD-NOTES.md, "A run-to-run spread that
depends on temperature"; fifth review of issue 31, F14). The campaign is the CI test's
(Pooling.ANewRunFallsInItsPredictionIntervalAtEveryTemperatureWhenTheSpreadGrowsWithIt): 5 runs
at 4, 12, 20, 28, 36 degC, dN_i = line + a_i + b_i (T - 20) + e_i, a ~ N(0, 0.000959^2),
b ~ N(0, s_b^2) with s_b = 8.75e-5 /degC (a spread that grows away from 20 degC) or 0 (a constant
spread), e_i ~ N(0, se_i^2), se_i uniform in 4.9e-5-9.1e-5; then one new run at 4, 20 and 36 degC.
Share of campaigns whose 68.3 % prediction band holds it, with the band of:
  raw      the moment estimates untruncated (main before F14)
  nnls     non-negative least squares on the moment equations (Lawson & Hanson 1974)
  reml     REML under t0, t1 >= 0 (Patterson & Thompson 1971), Fisher scoring on the active set
  pretest  nnls, used where the untruncated t1 is at least C of its standard error (Bancroft
           1944), else the constant-tau^2 band: what method::fit_delta_n_random_effects does (C
           0.85)
  pretest0 the same, with t1 = 0 and t0 from the moments alone where the test fails
Each band is floored at the line's own interval (interval_at) except raw's; "below" counts the
tests where the band, unfloored, was below it. The formulas are delta_n_model.cpp's, in numpy.

Usage: /usr/bin/python3 bench/pooling_spread_estimators.py [--campaigns=N] [--seed=S]
       [--estimators=raw,nnls,reml,pretest:0.85]"""
import math
import sys

import numpy as np

P68 = 0.5 + 0.5 * math.erf(1 / math.sqrt(2))
_T_CACHE = {}


def _betacf(a, b, x):
    qab, qap, qam = a + b, a + 1, a - 1
    c, d = 1.0, 1 - qab * x / qap
    d = 1 / (d if abs(d) > 1e-300 else 1e-300)
    h = d
    for m in range(1, 300):
        m2 = 2 * m
        for aa in (m * (b - m) * x / ((qam + m2) * (a + m2)),
                   -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2))):
            d = 1 + aa * d
            d = 1 / (d if abs(d) > 1e-300 else 1e-300)
            c = 1 + aa / c
            c = c if abs(c) > 1e-300 else 1e-300
            h *= d * c
        if abs(d * c - 1) < 3e-14:
            break
    return h


def _t_cdf(t, nu):
    """Student's t distribution function (regularized incomplete beta, Numerical Recipes 6.4)."""
    x = nu / (nu + t * t)
    a, b = nu / 2, 0.5
    bt = math.exp(math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) +
                  b * math.log(1 - x))
    ib = bt * _betacf(a, b, x) / a if x < (a + 1) / (a + b + 2) else 1 - bt * _betacf(b, a, 1 - x) / b
    return 1 - 0.5 * ib if t > 0 else 0.5 * ib


def t_one_sigma(nu):
    if nu >= 1e5:
        return 1.0
    key = round(nu, 3)
    if key not in _T_CACHE:
        lo, hi = 0.5, 50.0
        for _ in range(60):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if _t_cdf(mid, nu) < P68 else (lo, mid)
        _T_CACHE[key] = (lo + hi) / 2
    return _T_CACHE[key]


def wls(X, y, w):
    A = np.linalg.inv(X.T @ (w[:, None] * X))
    b = A @ (X.T @ (w * y))
    r = y - X @ b
    return b, A, float(np.sum(w * r * r))


def fit(T, y, se):
    """fit_delta_n_random_effects, degree 1: DerSimonian-Laird tau^2, modified Knapp-Hartung."""
    k = len(T)
    x = T - T.mean()
    X = np.column_stack([np.ones(k), x])
    v = se ** 2
    w = 1 / v
    _, A, chi2 = wls(X, y, w)
    denom = w.sum() - np.trace(A @ (X.T @ ((w * w)[:, None] * X)))
    tau2 = max(0.0, (chi2 - (k - 2)) / denom) if denom > 0 else 0.0
    w = 1 / (v + tau2)
    b, A, chi2 = wls(X, y, w)
    q = max(1.0, chi2 / (k - 2))
    return dict(k=k, t_ref=T.mean(), x=x, X=X, v=v, y=y, w=w, b=b, A=A, cov=A * q, dof=k - 2,
                tau2=tau2, new_var=q * (tau2 + v.mean()),
                gate=len(set(np.abs(x))) >= 2 and tau2 >= 5 * v.mean())


def moments(m):
    """The moment equations E z = t0 d0 + t1 d1 of the squared residuals, and their LS solution."""
    X, w, v, y, x = m["X"], m["w"], m["v"], m["y"], m["x"]
    R = np.eye(m["k"]) - X @ m["A"] @ X.T * w[None, :]
    M = R * R
    D = np.column_stack([M.sum(1), M @ (x * x)])
    z = (R @ y) ** 2 - M @ v
    L = np.linalg.solve(D.T @ D, D.T)
    return dict(R=R, D=D, z=z, L=L, t=L @ z)


def var_of(m, e, lin):
    S = np.maximum(m["v"] + e["t"][0] + e["t"][1] * m["x"] ** 2, m["v"])
    C = e["R"] @ np.diag(S) @ e["R"].T
    return float(2 * lin @ (C * C) @ lin)


def nnls(e):
    if e["t"][0] >= 0 and e["t"][1] >= 0:
        return e
    z, D = e["z"], e["D"]
    cands = [np.zeros((2, len(z)))]
    for j in (0, 1):
        lj = D[:, j] / (D[:, j] @ D[:, j])
        if lj @ z >= 0:
            L = np.zeros((2, len(z)))
            L[j] = lj
            cands.append(L)
    L = min(cands, key=lambda L: np.sum((z - D @ (L @ z)) ** 2))
    return dict(e, L=L, t=L @ z)


def reml(m):
    X, v, y, x = m["X"], m["v"], m["y"], m["x"]
    Vk = [np.ones(m["k"]), x * x]
    th = np.array([max(m["tau2"], 1e-3 * v.mean()), 0.0])

    def proj(th):
        Vi = np.diag(1 / (v + th[0] + th[1] * x * x))
        return Vi - Vi @ X @ np.linalg.inv(X.T @ Vi @ X) @ X.T @ Vi

    for _ in range(50):
        P = proj(th)
        Py = P @ y
        s = np.array([-0.5 * (np.trace(P * Vk[a][None, :]) - Py @ (Vk[a] * Py)) for a in (0, 1)])
        info = np.array([[0.5 * np.trace((P * Vk[a][None, :]) @ (P * Vk[b][None, :]))
                          for b in (0, 1)] for a in (0, 1)])
        act = [i for i in (0, 1) if not (th[i] <= 0 and s[i] <= 0)]
        step = np.zeros(2)
        if act:
            step[act] = np.linalg.solve(info[np.ix_(act, act)], s[act])
        new = np.maximum(th + step, 0)
        done = np.max(np.abs(new - th)) <= 1e-10 * (th.sum() + v.mean())
        th = new
        if done:
            break
    P = proj(th)
    info = np.array([[0.5 * np.trace((P * Vk[a][None, :]) @ (P * Vk[b][None, :]))
                      for b in (0, 1)] for a in (0, 1)])
    act = [i for i in (0, 1) if th[i] > 0]
    cov = np.zeros((2, 2))
    if act:
        cov[np.ix_(act, act)] = np.linalg.inv(info[np.ix_(act, act)])
    return th, cov


def line_interval(m, T):
    xv = np.array([1, T - m["t_ref"]])
    return t_one_sigma(m["dof"]) * math.sqrt(xv @ m["cov"] @ xv)


def constant_band(m, T):
    xv = np.array([1, T - m["t_ref"]])
    return t_one_sigma(m["dof"]) * math.sqrt(xv @ m["cov"] @ xv + m["new_var"])


def spread_band(m, T, t, lin_var):
    """t(nu) sqrt(V), V = tau^2(T) + mean v + sum g^2 (v + tau^2(T_j)); lin_var(c) = var of V."""
    X, w, v, x = m["X"], m["w"], m["v"], m["x"]
    xn = T - m["t_ref"]
    g = (X @ m["A"] @ np.array([1, xn])) * w
    cst = v.mean() + np.sum(g * g * v)
    c = np.array([1 + np.sum(g * g), xn * xn + np.sum(g * g * x * x)])
    var = max(cst + c @ t, cst)
    vv = lin_var(c)
    nu = min(max(2 * var * var / vv, 1), 1e6) if vv > 0 else 1e6
    return t_one_sigma(nu) * math.sqrt(var)


def band_of(name, m, T):
    """The band, and whether it is floored at the line's interval."""
    if not m["gate"]:
        return constant_band(m, T), True
    if name == "reml":
        th, cov = reml(m)
        return spread_band(m, T, th, lambda c: c @ cov @ c), True
    e = moments(m)
    if name.startswith("pretest"):
        cut = float(name.split(":")[1])
        if not e["t"][1] > cut * math.sqrt(var_of(m, e, e["L"][1])):
            if not name.startswith("pretest0"):
                return constant_band(m, T), True
            d0 = e["D"][:, 0]
            L = np.zeros((2, m["k"]))
            L[0] = d0 / (d0 @ d0) if d0 @ e["z"] > 0 else 0.0
            e = dict(e, L=L, t=L @ e["z"])
    if name != "raw":
        e = nnls(e)
    return spread_band(m, T, e["t"], lambda c: var_of(m, e, c @ e["L"])), name != "raw"


def main():
    opts = dict(a[2:].split("=", 1) for a in sys.argv[1:])
    n, seed = int(opts.get("campaigns", 3000)), int(opts.get("seed", 5))
    names = opts.get("estimators", "raw,nnls,reml,pretest:0.85").split(",")
    temps, tests = np.array([4.0, 12, 20, 28, 36]), [4.0, 20.0, 36.0]
    print(f"{n} campaigns, seed {seed}; coverage at 4 / 20 / 36 degC (binomial std "
          f"{math.sqrt(0.683 * 0.317 / n):.3f}); below: band under the line's interval")
    for s_b in (8.75e-5, 0.0):
        for name in names:
            rng = np.random.default_rng(seed)
            hits, below = np.zeros(3), 0

            def draw(T):
                se = 7e-5 * (0.7 + 0.6 * rng.random(np.shape(T)))
                u = 0.000959 * rng.standard_normal(np.shape(T)) + \
                    s_b * rng.standard_normal(np.shape(T)) * (T - 20)
                return 3.09e-3 + 4.5e-5 * (T - 20) + u + se * rng.standard_normal(np.shape(T)), se

            for _ in range(n):
                m = fit(temps, *draw(temps))
                for j, T in enumerate(tests):
                    fresh, _ = draw(np.array(T))
                    miss = abs(float(fresh) - (m["b"][0] + m["b"][1] * (T - m["t_ref"])))
                    band, floored = band_of(name, m, T)
                    line = line_interval(m, T)
                    below += band < line
                    hits[j] += miss <= (max(band, line) if floored else band)
            spread = "grows" if s_b > 0 else "constant"
            print(f"spread {spread:8} {name:12} " + " / ".join(f"{h / n:.3f}" for h in hits) +
                  f"  below {below} of {3 * n}", flush=True)


if __name__ == "__main__":
    main()
