"""Confidence intervals, EDF and noise identification of `gyroflip.allantools` (allantools' ci
module): chi-squared quantiles and Greenhall & Riley's EDF from gyroflip's C++ core, the rest in
NumPy. No scipy."""

import math

import numpy as np

from .. import _gyroflip

ONE_SIGMA_CI = math.erf(1.0 / math.sqrt(2.0))  # 0.6826894921370859


def _chi2_quantile(p, edf):
    """The chi-squared quantile with scipy.stats.chi2.ppf's edge values (allantools calls it):
    0 at p = 0, inf at p = 1, NaN for p outside [0, 1] (as ci > 2 makes it) or edf <= 0 or NaN."""
    if not edf > 0.0 or not 0.0 <= p <= 1.0:
        return math.nan
    if p <= 0.0:
        return 0.0
    if p >= 1.0:
        return math.inf
    return _gyroflip._chi2_quantile(p, edf)


def confidence_interval(dev, edf, ci=ONE_SIGMA_CI):
    """(dev_min, dev_max) at two-sided confidence ci for EDF edf (SP1065 eqn 45); dev a number or
    an array (elementwise, as allantools' NumPy arithmetic), edf a number. ci = 1 gives (0, inf),
    edf <= 0 (NaN, NaN), as allantools through scipy."""
    lo_p = min(abs(ci), abs(ci - 1.0)) / 2.0
    edf = float(edf)
    variance = np.asarray(dev, dtype=float) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        return (np.sqrt(edf * variance / _chi2_quantile(1.0 - lo_p, edf)),
                np.sqrt(edf * variance / _chi2_quantile(lo_p, edf)))


def edf_greenhall(alpha, d, m, N, overlapping=False, modified=False, verbose=False):
    """Greenhall & Riley's EDF (2003) for noise alpha, difference order d (1, 2 Allan, 3
    Hadamard), factor m and N phase points, modified or not, overlapping or not. Where the paper
    defines none (alpha + 2d <= 1, alpha outside -4..2) ValueError (allantools: AssertionError)."""
    e = _gyroflip._edf(int(alpha), int(d), int(m), int(N), bool(overlapping), bool(modified))
    if verbose:
        print("edf_greenhall:", e)
    return e


def edf_totdev(N, m, alpha):
    """TOTDEV's EDF: SP1065 b (N/m) - c for alpha = 0, -1, -2, else edf_simple (as allantools)."""
    alpha = int(alpha)
    if alpha in (0, -1, -2):
        b, c = [(1.50, 0.0), (1.17, 0.22), (0.93, 0.36)][abs(alpha)]
        return b * (float(N) / float(m)) - c
    return edf_simple(N, m, alpha)


def edf_mtotdev(N, m, alpha):
    """MTOTDEV's EDF: SP1065 Table 8, b (N/m) - c."""
    if alpha not in (2, 1, 0, -1, -2):
        raise ValueError(f"alpha must be 2, 1, 0, -1 or -2 (got {alpha})")
    b, c = [(1.90, 2.1), (1.20, 1.40), (1.10, 1.2), (0.85, 0.50), (0.75, 0.31)][abs(alpha - 2)]
    return b * (float(N) / float(m)) - c


def edf_simple(N, m, alpha):
    """SP1065 Table 5's OADEV EDF for alpha 2, 1, 0, -1, -2; N - 1 for any other value."""
    N, m = float(N), float(m)
    if alpha == 2:
        return (N + 1) * (N - 2 * m) / (2 * (N - m))
    if alpha == 1:  # NaN (as allantools' np.log) where (N - 1) / (2 m) < 1 < (2 m + 1)(N - 1) / 4
        with np.errstate(invalid="ignore", divide="ignore"):
            return float(np.exp(np.sqrt(np.log((N - 1) / (2 * m)) * np.log((2 * m + 1) * (N - 1) / 4))))
    if alpha == 0:
        return (3 * (N - 1) / (2 * m) - 2 * (N - 2) / N) * 4 * m * m / (4 * m * m + 5)
    if alpha == -1:
        return 2 * (N - 2) / (2.3 * N - 4.9) if m == 1 else 5 * N * N / (4 * m * (N + 3 * m))
    if alpha == -2:
        return (N - 2) / (m * (N - 3) ** 2) * ((N - 1) ** 2 - 3 * m * (N - 1) + 4 * m * m)
    return N - 1


def lag1_acf(x, detrend_deg=1):
    """Lag-1 autocorrelation of x (Riley & Greenhall 2004, eqn 2)."""
    x = np.asarray(x, dtype=float)
    d = x - np.mean(x)
    return float(np.dot(d[:-1], d[1:]) / np.dot(d, d))


def detrend(x, deg=1):
    """x less its least-squares polynomial of degree deg."""
    t = np.arange(len(x))
    return np.asarray(x, dtype=float) - np.polyval(np.polyfit(t, x, deg), t)


def autocorr_noise_id(x, af, data_type="phase", dmin=0, dmax=2):
    """Lag-1 autocorrelation noise identification (Riley & Greenhall 2004): phase decimated by af
    and detrended (quadratic), or frequency averaged over af and detrended (linear); differenced
    until rho = r1/(1 + r1) < 0.25 (dmin <= d <= dmax). Returns (alpha_int, alpha, d, rho).
    Fewer than 30 points raise NotImplementedError (as allantools)."""
    x = np.asarray(x, dtype=float)
    af = int(af)
    if data_type == "phase":
        z = detrend(x[::af], 2)
        add = 2
    elif data_type == "freq":
        n = len(x) - len(x) % af
        z = detrend(x[:n].reshape(-1, af).mean(axis=1), 1)
        add = 0
    else:
        raise ValueError(f"unknown data_type: {data_type!r}")
    if len(z) < 30:
        raise NotImplementedError(f"noise identification needs 30 points or more (got {len(z)})")
    d = 0
    while True:
        r1 = lag1_acf(z)
        rho = r1 / (1.0 + r1)
        if d >= dmin and (rho < 0.25 or d >= dmax):
            return int(-round(2 * rho) - 2 * d) + add, -2 * (rho + d) + add, d, rho
        z = np.diff(z)
        d += 1


def b1(x, af, rate):
    """B1 = standard variance / Allan variance of the fractional-frequency averages over af
    (Barnes 1969; SP1065 section 5.5.6): the frequency of phase x (s) at `rate` Hz is
    rate * diff(x), the ADEV taken at tau = af / rate, so B1 does not depend on rate.
    (allantools 2024.06's ci.b1 asks for tau = af * rate and does not scale diff(x) by rate,
    so it agrees with this one at rate 1 only; docs/python.md.)"""
    from .allantools import adev
    _, devs, _, _ = adev(x, taus=[af / rate], data_type="phase", rate=rate)
    y = np.diff(np.asarray(x, dtype=float)) * rate
    n = len(y) - len(y) % af
    ya = y[:n].reshape(-1, af).mean(axis=1)
    return float(np.var(ya, ddof=1) / devs[0] ** 2)


def b1_theory(N, mu):
    """Expected B1 for N frequency averages and AVAR ~ tau^mu (Barnes; SP1065 eqn 67)."""
    N = float(N)
    if mu == 2:
        return N * (N + 1.0) / 6.0
    if mu == 1:
        return N / 2.0
    if mu == 0:
        return N * math.log(N) / (2.0 * (N - 1.0) * math.log(2))
    if mu == -1:
        return 1.0
    if mu == -2:
        return (N * N - 1.0) / (1.5 * N * (N - 1.0))
    return N * (1.0 - N ** mu) / (2 * (N - 1.0) * (1 - 2.0 ** mu))


def b_to_mu(b):
    """mu (AVAR ~ tau^mu) of phase-PSD exponent b (alpha = b + 2)."""
    return {2: -2, 1: -2, 0: -1, -1: 0, -2: 1, -3: 2, -4: 3}[b + 2]


def b1_boundary(b_hi, N):
    """Geometric mean of the B1 of b_hi and b_hi - 1."""
    return math.sqrt(b1_theory(N, b_to_mu(b_hi - 1)) * b1_theory(N, b_to_mu(b_hi)))


def b1_noise_id(x, af, rate):
    """gyroflip's own noise identification (allantools 2024.06 has none in its package; its
    examples/b1_noise_id_figure.py has a b1_noise_id that returns the B1 ratio): alpha 2 (white
    PM), 1 (flicker PM), 0 (white FM), -1 (flicker FM) or -2 (random-walk FM) of phase x at
    averaging factor af, the B1 ratio against the boundaries between neighbouring noise types
    (geometric means of b1_theory for the n = (len(x) - 1) // af averages), then for PM, whose B1
    is the same for both, R(n) = MVAR / AVAR against rn_boundary (SP1065 section 5.5.6, Howe,
    Beard, Greenhall & Riley 2000). At af = 1 MDEV is ADEV, so R(1) = 1 for every noise and says
    nothing: white and flicker PM cannot be told apart there and PM is returned as flicker PM (1,
    the type with the smaller EDF: wider intervals); use af >= 2 to split them."""
    b = b1(x, af, rate)
    n = (len(x) - 1) // af
    # b = alpha - 2 is the phase-PSD exponent; b1_boundary(b_hi) splits b_hi from b_hi - 1.
    for b_hi, alpha in ((-3, -2), (-2, -1), (-1, 0)):
        if b > b1_boundary(b_hi, n):
            return alpha
    return 1 if rn(x, af, rate) > rn_boundary(af, 0) else 2


def rn(x, af, rate):
    """R(n) = MVAR / AVAR at factor af (tau = af / rate; allantools' ci.rn asks for af * rate)."""
    from .allantools import adev, mdev
    _, a, _, _ = adev(x, taus=[af / rate], data_type="phase", rate=rate)
    _, md, _, _ = mdev(x, taus=[af / rate], data_type="phase", rate=rate)
    return float((md[0] / a[0]) ** 2)


def rn_theory(af, b):
    """R(n) expected for phase-PSD exponent b (white PM 1/af, flicker PM with f_h = 1/(2 tau0))."""
    if b == 0:
        return 1.0 / af
    if b == -1:
        avar = (1.038 + 3 * math.log(2 * math.pi * 0.5 * af)) / (4.0 * math.pi ** 2)
        return 3 * math.log(256.0 / 27.0) / (8.0 * math.pi ** 2) / avar
    return 1.0


def rn_boundary(af, b_hi):
    return math.sqrt(rn_theory(af, b_hi) * rn_theory(af, b_hi - 1))


def confidence_interval_noiseID(x, dev, af, dev_type="adev", data_type="phase", ci=ONE_SIGMA_CI):
    """(dev_min, dev_max): noise identified by autocorr_noise_id at af, Greenhall's EDF for
    dev_type (adev, oadev, mdev, tdev, hdev, ohdev), chi-squared bounds."""
    dmax = 3 if dev_type in ("hdev", "ohdev") else 2
    alpha = autocorr_noise_id(x, int(af), data_type=data_type, dmin=0, dmax=dmax)[0]
    spec = {"adev": (2, False, False), "oadev": (2, True, False), "mdev": (2, True, True),
            "tdev": (2, True, True), "hdev": (3, False, False), "ohdev": (3, True, False)}
    if dev_type not in spec:
        raise NotImplementedError(f"no EDF for {dev_type}")
    d, ovl, mod = spec[dev_type]
    edf = edf_greenhall(alpha, d, af, len(x), overlapping=ovl, modified=mod)
    return confidence_interval(dev, edf, ci)
