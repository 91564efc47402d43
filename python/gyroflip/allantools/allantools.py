"""The statistics and helpers of `gyroflip.allantools` (docs/python.md, "The allantools drop-in").

Every deviation takes (data, rate=1.0, data_type="phase", taus=None) and returns
(taus, devs, errs, ns) as allantools 2024.06 does, computed by gyroflip's C++ core:
- data: phase (seconds, or deg for a gyro) or fractional frequency (data_type="freq"); a 1-D
  array or an (N, 1) column. Frequency data lose their leading and trailing NaN (trim_data);
  a NaN inside the data gives NaN deviations (GRADEV takes NaN as gaps instead).
- taus: None/"octave", "decade", "all", "log10" or taus in seconds (rounded to the nearest
  averaging factor; NaN, non-positive and too long taus dropped). A float32 array of taus gives
  float32 results.
- errs = devs / sqrt(ns) (theo1: devs / sqrt(N - m), tierms: zeros, as allantools); points with
  ns <= 1 are dropped; none left, or too few points, raises NoValidTau (a UserWarning, as
  allantools raises UserWarning).
- a NaN or inf inside phase data blanks (NaN, or inf as numpy's sums give) only the taus whose
  terms read it for ADEV, HDEV, PDEV (strided or short of the end, as allantools), all taus for
  the other statistics and for frequency data.
- rate must be positive and finite: else RateError, both a ValueError and a RuntimeError
  (allantools raises RuntimeError for rate 0). Rates outside the core's [1e-9, 1e9] Hz are
  computed at 1 Hz and rescaled exactly (the deviations are linear in the phase).
Nothing here imports allantools or scipy.
"""

import math
import warnings

import numpy as np

from .. import _gyroflip

__version__ = "2024.06"


class RateError(ValueError, RuntimeError):
    """A sample rate that is not positive and finite (allantools: RuntimeError for rate 0)."""


class NoValidTau(UserWarning, ValueError):
    """No averaging time is left with two terms or more (allantools raises UserWarning)."""


# ---------------------------------------------------------------------------------------------
# Helpers


def _rate(rate):
    try:
        r = float(rate)
    except (TypeError, ValueError):
        raise RateError(f"rate must be a number of Hz (got {rate!r})") from None
    if not (r > 0.0 and math.isfinite(r)):
        raise RateError(f"rate must be a positive, finite sample rate in Hz (got {rate!r})")
    return r


def _column(data):
    """data as a 1-D float64 array: (N,) or (N, 1)."""
    a = np.asarray(data, dtype=np.float64)
    if a.ndim == 2 and 1 in a.shape:
        a = a.reshape(-1)
    if a.ndim != 1:
        raise ValueError(f"data must be 1-D or one column (got shape {a.shape})")
    return np.ascontiguousarray(a)


def trim_data(x):
    """x without its leading and trailing NaN (NaN inside stay): a slice of x, so a list stays a
    list and an array an array (as allantools)."""
    a = np.asarray(x, dtype=np.float64) if not isinstance(x, np.ndarray) else x
    if a.size == 0 or (not np.isnan(a[0]) and not np.isnan(a[-1])):
        return x  # the usual case, without a pass over the data
    finite = np.flatnonzero(~np.isnan(a))
    if finite.size == 0:
        return x[:0]
    return x[finite[0]:finite[-1] + 1]


def _float_dtype(a):
    """float32 for float32 input (allantools' NumPy arithmetic keeps it), else float64."""
    return np.float32 if getattr(a, "dtype", None) == np.float32 else np.float64


def frequency2phase(freqdata, rate):
    """Phase (s) from fractional frequency: trimmed of end NaN, mean removed, integrated, with a
    leading 0 (N samples give N + 1 phase points); float32 stays float32."""
    dt = 1.0 / _rate(rate)
    y = trim_data(_column(freqdata))
    y = y - np.nanmean(y) if y.size else y
    return np.concatenate(([0.0], np.cumsum(y) * dt)).astype(_float_dtype(freqdata))


def phase2frequency(phase, rate):
    """Fractional frequency rate * diff(phase) (N phase points give N - 1); float32 stays
    float32."""
    return (_rate(rate) * np.diff(np.asarray(phase, dtype=np.float64))).astype(_float_dtype(phase))


def phase2radians(phasedata, v0):
    """Phase in seconds to radians of a carrier of v0 Hz."""
    return 2.0 * np.pi * float(v0) * np.asarray(phasedata, dtype=np.float64)


def frequency2fractional(frequency, mean_frequency=-1):
    """Frequency in Hz to fractional frequency about mean_frequency (-1: the data's mean), as a
    list (as allantools)."""
    f = np.asarray(frequency, dtype=np.float64)
    mu = np.mean(f) if mean_frequency == -1 else float(mean_frequency)
    return list((f - mu) / mu)  # a list, as allantools' list comprehension


def input_to_phase(data, rate, data_type):
    if data_type == "phase":
        return _column(data)
    if data_type == "freq":
        return frequency2phase(data, rate)
    raise ValueError(f"unknown data_type: {data_type!r} (phase or freq)")


def tau_generator(data, rate, taus=None, v=False, even=False, maximum_m=-1):
    """(np.array(data), m, taus): the averaging factors m (float, sorted, unique,
    0 < m < len(data), m <= maximum_m unless -1, even only with even=True) for `taus` ("octave"
    by default, "all", "decade" 1, 2, 4, 10, 20, 40, ..., "log10" about 10 per decade, or taus in
    seconds) and the taus m / rate. Warns NoValidTau when nothing is left (allantools prints a
    warning)."""
    m, t = _tau_factors(len(data), rate, taus, v=v, even=even, maximum_m=maximum_m)
    if m.size == 0:
        warnings.warn(f"no averaging time fits {len(data)} points for taus {taus!r}", NoValidTau,
                      stacklevel=2)
    return np.array(data), m, t


def _tau_factors(n, rate, taus, v=False, even=False, maximum_m=-1):
    """tau_generator's (m, taus) for n points, without the data."""
    rate = _rate(rate)
    if taus is None or (isinstance(taus, list) and len(taus) == 0):
        taus = "octave"
    dtype = taus.dtype if isinstance(taus, np.ndarray) and taus.dtype == np.float32 else np.float64
    if isinstance(taus, str):
        if taus == "all":
            t = np.arange(1, n + 1, dtype=np.float64) / rate
        elif taus == "octave":
            t = 2.0 ** np.arange(0, int(np.floor(np.log2(n))) + 1 if n > 0 else 0) / rate
        elif taus == "log10":
            top = np.log10(n) if n > 0 else 0.0
            t = np.logspace(0, top, int(10 * top)) / rate
        elif taus == "decade":
            t = np.array([f * 10.0 ** k for k in range(int(np.floor(np.log10(n))) + 1 if n > 0 else 0)
                          for f in (1.0, 2.0, 4.0)]) / rate
        else:
            raise ValueError(f"taus must be 'all', 'octave', 'decade', 'log10' or an array (got {taus!r})")
    else:
        t = np.asarray(taus, dtype=dtype).reshape(-1)
    m = np.round(t * np.asarray(rate, dtype=t.dtype))
    limit = n if maximum_m == -1 else maximum_m
    with np.errstate(invalid="ignore"):
        keep = (m > 0) & (m < n) & (m <= limit)
    m = np.unique(m[keep])
    if even:
        m = m[m % 2 == 0]
    if v:
        print("tau_generator:", m)
    return m, (m / np.asarray(rate, dtype=m.dtype)).astype(m.dtype)


def tau_reduction(ms, rate, n_per_decade):
    """At most n_per_decade of the factors ms per decade (where their rounded log10 steps)."""
    ms = np.int64(ms)
    keep = np.bool_(np.rint(n_per_decade * np.log10(ms[1:])) -
                    np.rint(n_per_decade * np.log10(ms[:-1])))
    ms = ms[:-1][keep]
    return ms, ms / float(rate)


def remove_small_ns(taus, devs, deverrs, ns):
    """The points with ns > 1 (deverrs an array or a pair [lower, upper] of arrays); NoValidTau
    when none is left."""
    keep = np.asarray(ns) > 1
    if isinstance(deverrs, list):
        errs = [np.asarray(deverrs[0])[keep], np.asarray(deverrs[1])[keep]]
    else:
        errs = np.asarray(deverrs)[keep]
    if not np.any(keep):
        raise NoValidTau("no averaging time has two terms or more")
    return np.asarray(taus)[keep], np.asarray(devs)[keep], errs, np.asarray(ns)[keep]


# ---------------------------------------------------------------------------------------------
# The deviations


# The core takes sample intervals in [1e-9, 1e9] s (analysis::check_tau0); allantools has no
# bound. Outside it the drop-in runs the core at 1 Hz and rescales: every statistic is linear in
# the phase, the frequency ones (ADEV ... PDEV) scale as 1 / tau0 and the time ones as tau0^0,
# and frequency data integrate to phase in units of tau0.
_CORE_RATE_HZ = (1e-9, 1e9)
# The statistics in the unit of time (of angle): the library's table (analysis::dev_table).
_TIME_STATISTICS = tuple(f["name"] for f in _gyroflip._dev_facts() if f["angle_unit"])


def _core_rate(rate, data_type, kind):
    """(the rate the core runs at, the factor its deviations are multiplied by)."""
    if _CORE_RATE_HZ[0] <= rate <= _CORE_RATE_HZ[1]:
        return rate, 1.0
    power = (0 if kind in _TIME_STATISTICS else 1) - (1 if data_type == "freq" else 0)
    return 1.0, rate ** power


def _core(function, *args):
    """A call into the core, its "too short" errors as NoValidTau (allantools: UserWarning)."""
    try:
        return function(*args)
    except NoValidTau:
        raise
    except ValueError as e:
        text = str(e)
        if text.startswith("no averaging time") or "too few" in text:
            raise NoValidTau(text) from None
        raise


def _core_zeroing(function, *arrays):
    """(function(*arrays) from the core, whether the data were finite): the core refuses a
    non-finite sample; only then are they looked for, and the call repeated with them zeroed
    (no pass over the data in the usual case)."""
    try:
        return _core(function, *arrays), True
    except ValueError as e:
        if "not finite" not in str(e) and "infinite" not in str(e):
            raise
    return _core(function, *(np.where(np.isfinite(a), a, 0.0) for a in arrays)), False


# The terms of allantools' difference statistics: coefficients of x[i], x[i + m], x[i + 2m], ...
_SECOND_DIFFERENCE = (1.0, -2.0, 1.0)
_THIRD_DIFFERENCE = (-1.0, 3.0, -3.0, 1.0)


def _terms(x, m, stride, coefficients):
    """The difference terms sum_j c_j x[i + j m] for i = 0, stride, 2 stride, ... while
    i + (len(c) - 1) m < len(x) (SP1065 eqns 7 and 17 with stride m, eqns 11 and 18 with 1)."""
    last = len(coefficients) - 1
    n = len(range(last * m, len(x), stride))
    v = np.zeros(n)
    for j, c in enumerate(coefficients):
        v = v + c * x[j * m::stride][:n]
    return v


def _sum_of_terms(kind, x, m):
    """The sum of squared terms allantools forms for `kind` at factor m on phase x, so that a
    non-finite sample gives NaN or inf exactly where allantools' does (None: a statistic whose
    every term is not listed here, taken as NaN)."""
    if kind in ("adev", "oadev"):
        v = _terms(x, m, m if kind == "adev" else 1, _SECOND_DIFFERENCE)
    elif kind in ("hdev", "ohdev"):
        v = _terms(x, m, m if kind == "hdev" else 1, _THIRD_DIFFERENCE)
    elif kind == "pdev":
        if m == 1:
            return _sum_of_terms("oadev", x, 1)
        # Vernotte et al. 2016 eqn 4: sum_k ((m - 1)/2 - k)(x[i + k] - x[i + m + k]), i < N - 2m.
        count = len(x) - 2 * m
        if count < 1:
            return 0.0
        weights = (m - 1) / 2.0 - np.arange(m)
        v = np.correlate((x[:-m] - x[m:])[:count + m - 1], weights, "valid")
    else:
        return None
    return np.sum(v * v)


def _deviation(kind, data, rate, data_type, taus, maximum_m=None, even=False, on_freq=False):
    rate = _rate(rate)
    if data_type == "freq":
        samples = trim_data(_column(data))
        n_phase = len(samples) + 1
    elif data_type == "phase":
        samples = _column(data)
        n_phase = len(samples)
    else:
        raise ValueError(f"unknown data_type: {data_type!r} (phase or freq)")
    if n_phase < 3:
        raise NoValidTau(f"{n_phase} phase points are too few for a deviation")
    # allantools generates HTOTDEV's taus on the frequency (N - 1 points) with m <= that / 3,
    # MTOTDEV's and TTOTDEV's on the phase with m <= N / 3.
    n_gen = n_phase - 1 if on_freq else n_phase
    limit = -1 if maximum_m is None else maximum_m(n_gen)
    m, t = _tau_factors(n_gen, rate, taus, even=even, maximum_m=limit)
    dtype = t.dtype
    if m.size == 0:
        raise NoValidTau(f"no averaging time fits {n_phase} phase points for taus {taus!r}")
    # Frequency data go to the core as rate samples (it removes the mean and integrates, as
    # frequency2phase does, without a phase array in Python). Non-finite samples are zeroed for
    # the core, and each tau whose terms touch one gets allantools' NaN or inf (all taus for
    # frequency data, whose integral is NaN from there on).
    factors = [int(v) for v in m]
    kind_in = "rate" if data_type == "freq" else "angle"
    if data_type == "freq" and kind in ("mtie", "tierms") and samples.size:
        # gyroflip's MTIE and TIE rms keep a rate record's mean (ITU-T G.810); allantools'
        # frequency2phase removes it first, so the drop-in does too.
        samples = samples - np.nanmean(samples)
    core_rate, scale = _core_rate(rate, data_type, kind)
    r, finite = _core_zeroing(
        lambda y: _gyroflip._curve(kind, y, core_rate, kind_in, "octave", factors, None, False), samples)
    by_m = {int(mm): (d, n) for mm, d, n in zip(r["m"], r["dev"], r["n"])}
    devs = np.array([by_m.get(int(mm), (0.0, 0))[0] for mm in m], dtype=np.float64) * scale
    ns = np.array([by_m.get(int(mm), (0.0, 0))[1] for mm in m], dtype=np.float64)
    if not finite:
        for i, mm in enumerate(factors):
            total = None if data_type == "freq" else _sum_of_terms(kind, samples, mm)
            if total is None or not np.isfinite(total):
                devs[i] = np.nan if total is None else total
    with np.errstate(divide="ignore", invalid="ignore"):
        if kind == "theo1":  # allantools: devs / sqrt(N - m) (ns are its (N - m) m / 2 terms)
            errs = devs / np.sqrt(n_phase - m.astype(np.float64))
        elif kind == "tierms":  # allantools returns zeros ("TODO! I THINK THIS IS WRONG!")
            errs = np.zeros_like(devs)
        else:
            errs = devs / np.sqrt(ns)
    taus_out, devs, errs, ns = remove_small_ns(t, devs, errs, ns)
    return (taus_out.astype(dtype), devs.astype(dtype), errs.astype(dtype), ns.astype(dtype))


def _make(kind, what, **options):
    def f(data, rate=1.0, data_type="phase", taus=None):
        return _deviation(kind, data, rate, data_type, taus, **options)
    f.__name__ = f.__qualname__ = kind
    f.__doc__ = (f"{what}: (taus, devs, errs, ns) of `data` (phase or data_type='freq'), computed "
                 "by gyroflip's core; see the module's doc for the shared rules.")
    return f


adev = _make("adev", "Allan deviation (SP1065 eqn 7)")
oadev = _make("oadev", "Overlapping Allan deviation (SP1065 eqn 11)")
mdev = _make("mdev", "Modified Allan deviation (SP1065 eqn 14)")
tdev = _make("tdev", "Time deviation (SP1065 eqn 15)")
hdev = _make("hdev", "Hadamard deviation (SP1065 eqn 17)")
ohdev = _make("ohdev", "Overlapping Hadamard deviation (SP1065 eqn 18)")
totdev = _make("totdev", "Total deviation (SP1065 eqn 25)")
mtotdev = _make("mtotdev", "Modified total deviation (SP1065 eqn 27, no bias correction)",
                maximum_m=lambda n: n / 3.0)
ttotdev = _make("ttotdev", "Time total deviation (SP1065 eqn 28)", maximum_m=lambda n: n / 3.0)
htotdev = _make("htotdev", "Hadamard total deviation (SP1065 eqn 29, OHDEV at m = 1)",
                maximum_m=lambda n: n / 3.0, on_freq=True)
theo1 = _make("theo1", "Theo1 (SP1065 eqn 30; even m, taus m / rate)", even=True)
pdev = _make("pdev", "Parabolic deviation (Vernotte et al. 2016)")
mtie = _make("mtie", "Maximum time interval error")
tierms = _make("tierms", "Rms time interval error")


def calc_adev_phase(phase, rate, mj, stride):
    """allantools' per-factor primitive (allantools.allantools only): (dev, deverr, n) of the
    Allan deviation at factor mj from the second differences taken every `stride` points
    (stride mj: ADEV, SP1065 eqn 7; 1: OADEV, eqn 11); no term: (0.0, 0.0, 1)."""
    mj = int(mj)
    v = _terms(_column(phase), mj, int(stride), _SECOND_DIFFERENCE)
    n = max(len(v), 1)
    dev = math.sqrt(float(np.sum(v * v)) / (2.0 * n)) * _rate(rate) / mj
    return dev, dev / math.sqrt(n), n


def calc_pdev_phase(phase, rate, mj):
    """allantools' per-factor primitive (allantools.allantools only): (dev, deverr, M) of the
    parabolic deviation at factor mj, M = N - 2 mj terms (Vernotte et al. 2016 eqn 4; OADEV at
    mj = 1); no term: (0, 0, 0)."""
    mj = int(mj)
    if mj == 1:
        return calc_adev_phase(phase, rate, 1, 1)
    x = _column(phase)
    count = len(x) - 2 * mj
    if count < 1:
        return 0, 0, 0
    dev = math.sqrt(72.0 * float(_sum_of_terms("pdev", x, mj)) / (count * mj ** 4)) * _rate(rate) / mj
    return dev, dev / math.sqrt(count), count


def calc_hdev_phase(phase, rate, mj, stride):
    """allantools' per-factor primitive: (dev, deverr, n) of the Hadamard deviation at factor mj
    from the third differences taken every `stride` points (stride mj: HDEV, SP1065 eqn 17;
    1: OHDEV, eqn 18; any other stride as allantools); no term: (0.0, 0.0, 1)."""
    mj = int(mj)
    v = _terms(_column(phase), mj, int(stride), _THIRD_DIFFERENCE)
    n = max(len(v), 1)
    dev = math.sqrt(float(np.sum(v * v)) / (6.0 * n)) * _rate(rate) / mj
    return dev, dev / math.sqrt(n), n


def _at_factor(kind, samples, rate, data_type, m):
    """(dev, deverr, n) of one statistic at one factor from the core, n = 1 kept (allantools'
    calc_* primitives return it)."""
    core_rate, scale = _core_rate(_rate(rate), data_type, kind)
    r = _core(_gyroflip._curve, kind, _column(samples), core_rate,
              "rate" if data_type == "freq" else "angle", "octave", [int(m)], None, False)
    dev, n = float(r["dev"][0]) * scale, int(r["n"][0])
    return dev, dev / math.sqrt(n), n


def calc_mtotdev_phase(phase, rate, m):
    """(dev, deverr, n) of MTOTDEV at factor m."""
    return _at_factor("mtotdev", phase, rate, "phase", m)


def calc_htotdev_freq(freq, m):
    """(dev, deverr, n) of HTOTDEV at factor m > 1 on fractional frequency, rate 1 (at m = 1
    gyroflip's core gives OHDEV, as allantools' htotdev() does; its calc_htotdev_freq(y, 1)
    evaluates the total formula: docs/python.md)."""
    return _at_factor("htotdev", freq, 1.0, "freq", m)


def mtie_phase_fast(phase, rate=1.0, data_type="phase", taus=None):
    """MTIE at every m = 2^k - 1 (windows of 2^k points; allantools' binary decomposition), by
    gyroflip's sliding extrema."""
    n = len(phase)
    ks = 2 ** np.arange(1, int(np.floor(np.log2(n))) + 1) - 1 if n > 1 else np.array([])
    return mtie(phase, rate=rate, data_type=data_type, taus=ks / _rate(rate))


def _factor_list(n_phase, rate, taus):
    """The averaging factors (ints) of `taus` for n_phase points and their taus (float32 for
    float32 taus); NoValidTau when none fits."""
    if n_phase < 3:
        raise NoValidTau(f"{n_phase} phase points are too few for a deviation")
    m, t = _tau_factors(n_phase, rate, taus)
    if m.size == 0:
        raise NoValidTau(f"no averaging time fits {n_phase} points for taus {taus!r}")
    return [int(v) for v in m], t


def _input_samples(data, data_type):
    """data as a 1-D float64 array, frequency data without their end NaN, and its phase length."""
    y = _column(data)
    if data_type == "freq":
        y = trim_data(y)
        return y, len(y) + 1
    if data_type != "phase":
        raise ValueError(f"unknown data_type: {data_type!r} (phase or freq)")
    return y, len(y)


def gradev(data, rate=1.0, data_type="phase", taus=None, ci=0.9, noisetype="wp"):
    """Gap-resistant overlapping ADEV: NaN are missing samples, terms touching them left out.
    Returns (taus, devs, [err_lo, err_hi], ns) with the interval at confidence `ci` as distances
    below and above dev (EDF: edf_simple for noisetype 'wp', 'wf', 'fp', 'ff', 'rf', else N - 1;
    allantools' own error bars differ, docs/python.md)."""
    from .ci import confidence_interval, edf_simple
    rate = _rate(rate)
    y, n_phase = _input_samples(data, data_type)
    factors, t = _factor_list(n_phase, rate, taus)
    core_rate, scale = _core_rate(rate, data_type, "oadev")
    r = _core(_gyroflip._gradev, y, core_rate, "rate" if data_type == "freq" else "angle", factors)
    keep = np.isin(np.asarray(factors), r["m"])
    devs = r["dev"] * scale
    alpha = {"wp": 2, "wf": 0, "fp": 1, "ff": -1, "rf": -2}.get(noisetype)
    n_valid = int(np.count_nonzero(~np.isnan(y)))
    lo, hi = [], []
    for d, mm, n in zip(devs, r["m"], r["n"]):
        if n > 1:
            e = edf_simple(n_valid, mm, alpha)
            a, b = confidence_interval(d, e, ci)
            lo.append(d - a)
            hi.append(b - d)
        else:
            lo.append(0.0)
            hi.append(0.0)
    dtype = t.dtype
    taus_out, devs, (lo, hi), ns = remove_small_ns(t[keep], devs, [np.array(lo), np.array(hi)],
                                                   r["n"].astype(np.float64))
    return (taus_out.astype(dtype), devs.astype(dtype), [lo.astype(dtype), hi.astype(dtype)],
            ns.astype(dtype))


def gcodev(data_1, data_2, rate=1.0, data_type="phase", taus=None):
    """Groslambert codeviation |cov|^(1/2) of two simultaneous series: (taus, devs, errs, ns),
    with the deviations' input rules (end NaN of frequency data trimmed, a NaN inside giving NaN,
    float32 taus float32 results)."""
    rate = _rate(rate)
    a, n_phase = _input_samples(data_1, data_type)
    b, _ = _input_samples(data_2, data_type)
    factors, t = _factor_list(n_phase, rate, taus)
    kind_in = "rate" if data_type == "freq" else "angle"
    core_rate, scale = _core_rate(rate, data_type, "oadev")
    r, finite = _core_zeroing(lambda u, v: _gyroflip._gcodev(u, v, core_rate, kind_in, factors), a, b)
    devs = np.abs(r["dev"]) * scale
    if not finite:  # allantools: NaN or inf where a term touches a non-finite sample
        for i, mm in enumerate(r["m"]):
            total = np.nan if data_type == "freq" else np.sum(
                _terms(a, int(mm), 1, _SECOND_DIFFERENCE) * _terms(b, int(mm), 1, _SECOND_DIFFERENCE))
            if not np.isfinite(total):
                devs[i] = np.abs(total)
    ns = r["n"].astype(np.float64)
    keep = np.isin(np.asarray(factors), r["m"])
    dtype = t.dtype
    taus_out, devs, errs, ns = remove_small_ns(t[keep], devs, devs / np.sqrt(ns), ns)
    return (taus_out.astype(dtype), devs.astype(dtype), errs.astype(dtype), ns.astype(dtype))


def three_cornered_hat_phase(phasedata_ab, phasedata_bc, phasedata_ca, rate, taus, function):
    """Clock A's deviation from three pairwise phase comparisons and a deviation `function`:
    var_A = (AB^2 + CA^2 - BC^2)/2, negative estimates as 0. Returns (taus, dev_a, err_a, ns_ab)."""
    t_ab, d_ab, _, n_ab = function(phasedata_ab, data_type="phase", rate=rate, taus=taus)
    _, d_bc, _, _ = function(phasedata_bc, data_type="phase", rate=rate, taus=taus)
    _, d_ca, _, _ = function(phasedata_ca, data_type="phase", rate=rate, taus=taus)
    var_a = 0.5 * (d_ab ** 2 + d_ca ** 2 - d_bc ** 2)
    dev_a = np.sqrt(np.maximum(var_a, 0.0))
    return t_ab, dev_a, [d / np.sqrt(n) for d, n in zip(dev_a, n_ab)], n_ab


# ---------------------------------------------------------------------------------------------
# Spectra and Allan deviations


def _simpson(y, x):
    """Composite Simpson's rule on samples y(x) (an odd count; the last interval by the
    trapezoid otherwise)."""
    y = np.asarray(y)
    x = np.asarray(x)
    n = x.size
    if n < 3:
        return np.trapz(y, x, axis=-1)
    last = n if n % 2 == 1 else n - 1
    h = np.diff(x[:last])
    h0, h1 = h[0::2], h[1::2]
    y0, y1, y2 = y[..., 0:last - 2:2], y[..., 1:last - 1:2], y[..., 2:last:2]
    hs = h0 + h1
    s = np.sum(hs / 6.0 * (y0 * (2.0 - h1 / h0) + y1 * hs * hs / (h0 * h1) + y2 * (2.0 - h0 / h1)),
               axis=-1)
    if last != n:
        s = s + 0.5 * (x[-1] - x[-2]) * (y[..., -1] + y[..., -2])
    return s


def psd2allan(S_y, f=1.0, kind="adev", base=2):
    """ADEV or MDEV from a one-sided PSD S_y (first element at f = 0; f the frequency step or the
    frequency array): sigma^2(tau) = 2 int S_y |sin^(k+1)(pi f tau)/(pi f tau)^k|^2 df, k = 1
    (adev) or 2 (mdev), by Simpson's rule on the PSD resampled 4 times finer (linear
    interpolation; allantools uses a cubic spline). taus: base^k tau0 (base <= 1: every m).
    Returns (taus, devs)."""
    if not isinstance(S_y, np.ndarray):
        raise ValueError("S_y must be a numpy array")
    if isinstance(f, np.ndarray):
        df = f[1] - f[0]
    elif np.isscalar(f):
        df = float(f)
    else:
        raise ValueError("f must be a frequency array or a frequency step")
    over = 4
    f0 = np.arange(S_y.size) * df * over
    fine = np.arange(df, (S_y.size - 1) * df * over + df, df)
    s = np.interp(fine, f0, S_y)
    fine = fine / over
    tau0 = 1.0 / np.max(fine)
    n = 1.0 / df / tau0 / 2.0
    if base > 1:
        m = np.unique(np.round(np.append(base ** np.arange(np.floor(np.log(n) / np.log(base))), n)))
    else:
        m = np.arange(1, n)
    taus = m * tau0
    k = 1.0 if kind[0].lower() == "a" else 2.0
    u = np.pi * fine[None, :] * taus[:, None]
    integrand = s[None, :] * np.abs(np.sin(u) ** (k + 1.0) / u ** k) ** 2
    integrand = np.concatenate((np.zeros((taus.size, 1)), integrand), axis=1)
    grid = np.concatenate(([0.0], fine))
    return taus, np.sqrt(2.0 * _simpson(integrand, grid))


def _kernel_integral(alpha, hadamard=False):
    """J(alpha) = int_0^inf u^alpha K(u) du with K the Allan (sin^4 u / u^2) or Hadamard
    ((4/3) sin^6 u / u^2) kernel, so that the variance of S_y = h f^alpha is
    2 h (pi tau)^(-alpha-1) J(alpha); closed form by the Mellin transform of powers of sine
    (alpha between -3 and 1, or -5 and 1 for Hadamard); the poles of Gamma at integers are
    taken as the mean of the two sides 1e-6 away (error ~1e-12)."""
    def j(a):
        s = a - 1.0  # int u^(s-1) sin^p u du
        if hadamard:  # sin^6 = (10 - 15 cos 2u + 6 cos 4u - cos 6u) / 32
            terms = [(-15.0, 2.0), (6.0, 4.0), (-1.0, 6.0)]
            scale, norm = 32.0, 4.0 / 3.0  # HVAR = (8/3) int S_y sin^6 / (pi f tau)^2
        else:  # sin^4 = (3 - 4 cos 2u + cos 4u) / 8
            terms = [(-4.0, 2.0), (1.0, 4.0)]
            scale, norm = 8.0, 1.0
        total = sum(c * b ** (-s) for c, b in terms)
        return norm * math.gamma(s) * math.cos(math.pi * s / 2.0) * total / scale
    if abs(alpha - round(alpha)) < 1e-9:
        return 0.5 * (j(alpha + 1e-6) + j(alpha - 1e-6))
    return j(alpha)


def _band_integral(h, a, lo, hi, tau, hadamard):
    """2 h int_lo^hi f^a K(pi f tau) df by Simpson's rule on a logarithmic grid (lo may be 0 and
    hi infinite: the grid then reaches 12 decades beyond the other end)."""
    lo_g = hi / 1e12 if lo <= 0 else lo
    hi_g = lo * 1e12 if not np.isfinite(hi) else hi
    lf = np.linspace(np.log(lo_g), np.log(hi_g), 4001)
    f = np.exp(lf)
    u = np.pi * f * tau
    k = (4.0 / 3.0) * np.sin(u) ** 6 / u ** 2 if hadamard else np.sin(u) ** 4 / u ** 2
    return 2.0 * h * _simpson(f ** a * k * f, lf)


def psd_piecewise_to_adev(h, alpha, f_nodes, taus, vartype="adev"):
    """ADEV (or HDEV) of a piecewise power-law PSD S_y = h_i f^alpha_i, segment i between the
    break frequencies f_nodes (ascending; none, or the two end nodes, for a single segment, whose
    variance is the closed form 2 h (pi tau)^(-alpha-1) J(alpha)); the segments' bands are
    integrated numerically."""
    h = np.atleast_1d(np.asarray(h, dtype=float))
    alpha = np.atleast_1d(np.asarray(alpha, dtype=float))
    taus = np.asarray(taus, dtype=float)
    had = vartype == "hdev"
    if h.size == 1:
        return np.sqrt(2.0 * h[0] * (np.pi * taus) ** (-alpha[0] - 1.0) *
                       _kernel_integral(alpha[0], had))
    nodes = np.asarray(f_nodes, dtype=float)
    edges = np.concatenate(([0.0], nodes, [np.inf]))
    var = np.zeros_like(taus)
    for t_i, tau in enumerate(taus):
        var[t_i] = sum(_band_integral(h[i], alpha[i], edges[i], edges[i + 1], tau, had)
                       for i in range(h.size))
    return np.sqrt(var)


def adev2psd_piecewise_approx(adevs, taus, vartype="adev"):
    """A piecewise power-law S_y = h_i f^alpha_i whose ADEV (or HDEV) follows the points: one
    segment per pair of neighbouring points (merged where slopes agree to 1e-6), alpha = -mu - 1
    from the local slope mu of the variance, h from the power-law relation; f_nodes at 1/tau of
    the breaks, ascending, with h and alpha in order of rising frequency (two end nodes for a
    single segment). Slopes outside the kernel's range
    (mu in (-2, 2) for ADEV, (-2, 4) for HDEV) raise ValueError. Returns
    (f_nodes, taus, h, alpha)."""
    adevs = np.asarray(adevs, dtype=float)
    taus = np.asarray(taus, dtype=float)
    mu = np.diff(np.log(adevs ** 2)) / np.diff(np.log(taus))
    hi_mu = 4.0 if vartype == "hdev" else 2.0
    if np.any(mu <= -2.0) or np.any(mu >= hi_mu):
        raise ValueError(f"variance slopes must lie in (-2, {hi_mu}) (got {mu.min()}..{mu.max()})")
    segs = [0]
    for i in range(1, mu.size):
        if abs(mu[i] - mu[segs[-1]]) > 1e-6:
            segs.append(i)
    h, alpha = [], []
    for i in segs:
        a = -mu[i] - 1.0
        j = _kernel_integral(a, vartype == "hdev")
        h.append(adevs[i] ** 2 / (2.0 * (np.pi * taus[i]) ** (-a - 1.0) * j))
        alpha.append(a)
    if len(segs) == 1:
        return np.array([1.0 / taus[-1], 1.0 / taus[0]]), taus, np.array(h), np.array(alpha)
    # Segments in order of rising frequency (falling tau), breaks at 1/tau of the break points.
    f_nodes = np.sort(np.array([1.0 / taus[i] for i in segs[1:]]))
    return f_nodes, taus, np.array(h[::-1]), np.array(alpha[::-1])
