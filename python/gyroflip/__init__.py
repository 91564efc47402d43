"""gyroflip: bias-drift compensation of MEMS gyroscopes by sign reversal (0/180 deg flipping).

The same C++ core as the `gyroflip` command, on NumPy arrays (docs/python.md):

- Allan family with allantools' signature: adev, oadev, mdev, tdev, hdev, ohdev, totdev
  (data, rate, data_type="phase", taus=None) -> (taus, devs, errs, ns); `rate` has no default
  here (a silent 1 Hz puts every tau and term off by the rate). For allantools code unchanged,
  rate=1.0 default included: gyroflip.allantools (gyroflip.allantools.install() makes
  `import allantools` load it).
- deviation(data, kind="oadev", rate=..., input="rate", taus="octave", ci=0.683): a
  Deviation with NumPy arrays tau_s, dev, ci_lo, ci_hi, edf, n, alpha (NIST SP1065 statistics,
  chi-squared bounds as Stable32 computes them).
- noise(...): the IEEE 952 noise terms with intervals (the keys of `gyroflip noise --json`), of a
  gyro or an accelerometer, one axis or several; plot(...): the noise figure (`noise --plot`);
  write_kalibr(...): Kalibr's IMU file; read_imu(path): an IMU CSV's columns, units and rate.
- calibrate(...), compensate(...): the paper's method (eqns 6-12) on a recording's columns;
  calibrate_runs(files): several recordings pooled, with dN(T), as `gyroflip calibrate`.
- simulate(...): the rig simulator; read_recording(path): a CSV or .gfr recording.
- report(files, output): the report folder `gyroflip report` writes (the same library call);
  reproduce(): the paper's experiment on the simulator, as `gyroflip reproduce`.

Units: rates in deg/s, angles in deg, times in s, temperatures in degC, unless a name says
otherwise. Errors raise ValueError (bad data or arguments) or OSError (files) with the messages
the command line prints. Long calls release the GIL and stop on Ctrl-C (KeyboardInterrupt).
"""

import json as _json
import mmap as _mmap
import numbers as _numbers
import os as _os
from dataclasses import dataclass as _dataclass

import numpy as _np
import operator as _operator
import warnings as _warnings

from . import _gyroflip

__version__ = _gyroflip.__version__

__all__ = [
    "adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "mtotdev", "ttotdev", "htotdev",
    "theo1", "pdev", "mtie", "tierms", "tau_generator",
    "Deviation", "deviation", "dynamic_deviation", "noise", "calibrate", "calibrate_runs",
    "compensate", "simulate", "read_recording", "report", "reproduce", "plan", "heading",
    "Imu", "read_imu", "plot", "write_kalibr",
    "__version__",
]


# ---------------------------------------------------------------------------------------------
# Arrays in


def _file_backed(a):
    """True when `a`'s memory is a shared mapping of a file (np.load(..., mmap_mode="r" or "r+"),
    np.memmap in those modes): its pages may then be handed back to the kernel as the analysis
    moves on and re-read from the page cache. Never for "c" (private copy-on-write) memmaps or
    ordinary arrays, whose pages hold the only copy of the data."""
    if not isinstance(a, _np.memmap) or getattr(a, "mode", None) not in ("r", "r+", "readonly", "readwrite"):
        return False
    return isinstance(getattr(a, "_mmap", None), _mmap.mmap)


def _samples(data, name="data"):
    """`data` as a 1-D C-contiguous float64 array (no copy when it is one already), and whether
    it is file-backed."""
    if isinstance(data, _np.ndarray) and data.dtype == _np.float64 and data.flags.c_contiguous:
        if data.ndim != 1:
            raise ValueError(f"{name} must be 1-D (got {data.ndim} dimensions)")
        return data, _file_backed(data)
    a = _np.ascontiguousarray(data, dtype=_np.float64)
    if a.ndim != 1:
        raise ValueError(f"{name} must be 1-D (got {a.ndim} dimensions)")
    return a, False


def _positive_rate(rate):
    if rate is None:
        raise ValueError("rate must be given: the sample rate in Hz (no default: a silent 1 Hz "
                         "puts every tau, and every noise term, off by the rate)")
    rate = float(rate)
    if not (rate > 0.0 and _np.isfinite(rate)):
        raise ValueError(f"rate must be a positive, finite sample rate in Hz (got {rate})")
    return rate


# ---------------------------------------------------------------------------------------------
# allantools-compatible functions

_DATA_TYPES = {"phase": "angle", "freq": "rate"}


def tau_generator(data, rate, taus=None, maximum_m=-1):
    """allantools' tau_generator: the averaging factors m (tau = m / rate) for `taus`.

    taus: None or "octave" (1, 2, 4, ... up to len(data)), "decade" (1, 2, 4, 10, 20, 40, ...),
    "all" (every m), "log10" (10 per decade), or an array of taus in seconds, each rounded to
    the nearest m (half to even, as numpy.round). Factors m < 1 or m >= len(data) are dropped,
    duplicates removed, the rest sorted. Returns (m as float64, taus in seconds)."""
    return _factors(len(data), rate, taus, maximum_m)


def _factors(n, rate, taus=None, maximum_m=-1):
    """tau_generator for a series of n points (only its length counts)."""
    rate = _positive_rate(rate)
    if taus is None or (isinstance(taus, (list, tuple)) and len(taus) == 0):
        taus = "octave"
    if isinstance(taus, str):
        if taus == "all":
            taus = (1.0 / rate) * _np.linspace(1.0, n, n)
        elif taus == "octave":
            maxn = _np.floor(_np.log2(n))
            taus = (1.0 / rate) * _np.logspace(0, int(maxn), int(maxn + 1), base=2.0)
        elif taus == "log10":
            maxn = _np.log10(n)
            taus = (1.0 / rate) * _np.logspace(0, maxn, int(10 * maxn), base=10.0)
        elif taus == "decade":
            maxn = int(_np.floor(_np.log10(n)))
            taus = [f * (1.0 / rate) * 10.0 ** k for k in range(maxn + 1) for f in (1.0, 2.0, 4.0)]
        else:
            raise ValueError(f"taus must be 'octave', 'decade', 'all', 'log10' or an array (got '{taus}')")
    taus = _np.asarray(taus, dtype=_np.float64)
    if not _np.all(_np.isfinite(taus)):
        raise ValueError("taus must be finite")
    if maximum_m == -1:
        maximum_m = n
    m = _np.round(taus * rate)
    m = m[(m < n) & (m > 0) & (m <= maximum_m)]
    m = _np.unique(m)
    return m, m / rate


def _compat(kind, data, rate, data_type, taus):
    if data_type not in _DATA_TYPES:
        raise ValueError(f"data_type must be 'phase' or 'freq' (got '{data_type}')")
    rate = _positive_rate(rate)
    y, backed = _samples(data)
    # allantools' phase series: the data (phase), or the frequency integrated to N + 1 points.
    n_phase = len(y) + (1 if data_type == "freq" else 0)
    m, _ = _factors(n_phase, rate, taus)
    if len(m) == 0:
        raise ValueError(f"no averaging factor left for {len(y)} samples and taus {taus!r}")
    r = _gyroflip._curve(kind, y, rate, _DATA_TYPES[data_type], "octave",
                         [int(v) for v in m], None, backed)
    # As allantools' remove_small_ns: points with fewer than two terms are dropped.
    keep = r["n"] > 1
    if not _np.any(keep):
        raise ValueError(f"no {kind} point has two terms or more for {len(y)} samples")
    ns = r["n"][keep].astype(_np.float64)
    devs = r["dev"][keep]
    # allantools reports tau = m / rate for every kind (Theo1 too, whose own tau is 0.75 m tau0).
    return r["m"][keep] / rate, devs, devs / _np.sqrt(ns), ns


def _compat_doc(kind, what, reference):
    return f"""{what} of `data`, allantools-compatible: returns (taus, devs, errs, ns).

    data: phase (data_type="phase", allantools' default; an angle in deg for a gyro) or
      fractional frequency (data_type="freq"; a rate in deg/s for a gyro), 1-D. A contiguous
      float64 array (np.load(..., mmap_mode="r") too) is read in place; other dtypes are
      converted once.
    rate: samples per second (Hz).
    taus: None/"octave", "decade", "all", "log10" or an array of taus (s), as allantools.
    Returns numpy arrays: taus (s), devs (the unit of the rate: deg/s for a gyro{', TDEV in deg' if kind == 'tdev' else ''}),
      errs = devs / sqrt(ns) (what allantools returns; for chi-squared bounds use
      gyroflip.deviation), ns = the number of terms in the sum (float, as allantools).
    Points with ns <= 1 are dropped, as allantools does. Formula: {reference}.
    Non-finite samples raise ValueError (allantools trims NaN at the ends instead)."""


def _compat_function(kind, what, reference):
    def f(data, rate, data_type="phase", taus=None):
        return _compat(kind, data, rate, data_type, taus)
    f.__name__ = f.__qualname__ = kind
    f.__doc__ = _compat_doc(kind, what, reference)
    return f


adev = _compat_function("adev", "Allan deviation (non-overlapping)", "NIST SP1065 eqn 7")
oadev = _compat_function("oadev", "Overlapping Allan deviation", "NIST SP1065 eqn 11")
mdev = _compat_function("mdev", "Modified Allan deviation", "NIST SP1065 eqn 14")
tdev = _compat_function("tdev", "Time deviation (tau MDEV / sqrt 3)", "NIST SP1065 eqn 15")
hdev = _compat_function("hdev", "Hadamard deviation (non-overlapping)", "NIST SP1065 eqn 17")
ohdev = _compat_function("ohdev", "Overlapping Hadamard deviation", "NIST SP1065 eqn 18")
totdev = _compat_function("totdev", "Total deviation", "NIST SP1065 eqn 25")
mtotdev = _compat_function("mtotdev", "Modified total deviation (no bias correction)",
                           "NIST SP1065 eqn 27")
ttotdev = _compat_function("ttotdev", "Time total deviation (tau MTOTDEV / sqrt 3)",
                           "NIST SP1065 eqn 28")
htotdev = _compat_function("htotdev", "Hadamard total deviation (no bias correction; OHDEV at m = 1)",
                           "NIST SP1065 eqn 29")
theo1 = _compat_function("theo1", "Theo1 deviation (even m; taus reported as m / rate, as allantools)",
                         "NIST SP1065 eqn 30")
pdev = _compat_function("pdev", "Parabolic deviation (OADEV at m = 1)",
                        "Vernotte et al. 2016, eqn 13")
mtie = _compat_function("mtie", "Maximum time interval error", "ITU-T G.810")
tierms = _compat_function("tierms", "Rms time interval error", "ITU-T G.810")


# ---------------------------------------------------------------------------------------------
# gyroflip's own interface


@_dataclass(frozen=True)
class Deviation:
    """One statistic's curve. Arrays, one entry per tau:
    tau_s (s), dev (the samples' rate unit, e.g. deg/s; TDEV in the angle unit), ci_lo and
    ci_hi (the bounds at level `ci`, NaN when ci=None), edf (equivalent degrees of freedom),
    n (terms in the sum, Stable32's "#"), alpha (the power-law noise exponent identified or
    given, as floats: 0 angle random walk, -1 bias instability, -2 rate random walk, 1/2 phase
    noise; NaN where none was read: ci=None without bias_correction, and pdev, mtie, tierms), m
    (the averaging factor). ci is None for pdev, mtie and tierms (no EDF)."""

    kind: str
    tau_s: _np.ndarray
    dev: _np.ndarray
    ci_lo: _np.ndarray
    ci_hi: _np.ndarray
    edf: _np.ndarray
    n: _np.ndarray
    alpha: _np.ndarray
    m: _np.ndarray
    ci: float


# Each statistic's facts, from the library's one table (analysis::dev_table), by name.
_DEV_FACTS = {f["name"]: f for f in _gyroflip._dev_facts()}
# The kinds SP1065 gives no EDF (analysis::has_edf): no bounds, no noise type, no level.
_WITHOUT_EDF = tuple(k for k, f in _DEV_FACTS.items() if not f["edf"])
# The kinds Stable32's bias correction applies to.
_BIAS_CORRECTED = tuple(k for k, f in _DEV_FACTS.items() if f["bias_correction"])


def _and_list(names):
    """'a, b and c'."""
    return ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else "".join(names)


def deviation(data, kind="oadev", rate=None, input="rate", taus="octave", ci=0.683, guard=False,
              bias_correction=False, alpha=None):
    """A deviation of the Allan family with confidence bounds, as `gyroflip adev` computes it.

    data: 1-D samples; input="rate" (deg/s, SP1065's frequency) or "angle" (deg, phase). A
      contiguous float64 array is read in place, and a memory-mapped file
      (np.load(path, mmap_mode="r")) in bounded memory, whatever its length.
    kind: "adev", "oadev", "mdev", "tdev", "hdev", "ohdev" or "totdev" (NIST SP1065 eqns 7, 11,
      14, 15, 17, 18, 25); "mtotdev", "ttotdev", "htotdev", "theo1" (eqns 27-30; Theo1's tau_s is
      0.75 m tau0; its taus are m / rate as allantools', m even: an odd one is dropped with a
      UserWarning), "pdev" (parabolic), "mtie", "tierms" (the angle unit). PDEV, MTIE and TIE rms
      have no bounds (ci_lo, ci_hi, edf, alpha NaN; guard refused); Theo1's are Howe & Peppler's
      EDF.
    rate: samples per second (Hz); required (ValueError without it).
    taus: "octave", "decade" (1, 2, 4, 10, 20, 40, ...) or "all" averaging factors, limited as
      Stable32 does (m <= (N-1)/5 for ADEV/HDEV, (N-1)/4 for OADEV/MDEV/TDEV/OHDEV, (N-1)/2
      for TOTDEV); or an array of taus in seconds (each rounded to the nearest factor).
    ci: two-sided confidence level of ci_lo/ci_hi (0.683 = 1 sigma; None = no bounds): noise
      identified at each tau (lag-1 autocorrelation, B1 ratio), EDF by Greenhall & Riley (2003),
      chi-squared bounds (SP1065 eqn 45), as Stable32 computes them.
    guard: no interval narrower than the noise types identified at the neighbouring taus allow
      (a guard against a type misread from a few points; `gyroflip adev --ci-guard`).
    bias_correction: MTOTDEV, TTOTDEV, HTOTDEV divided by Stable32's bias factor of the noise type
      identified at each tau (`gyroflip adev --bias-correction`).
    alpha: a known noise type for the bounds and the bias correction at every tau (2 white PM,
      1 flicker PM, 0 white FM, -1 flicker FM, -2 random-walk FM; Stable32's manual setting;
      `gyroflip adev --alpha`) instead of the type identified at each tau, so a tau's bounds and
      corrected value do not depend on the other taus asked for. Not with guard.
    Returns a Deviation. Releases the GIL; Ctrl-C stops it."""
    rate = _positive_rate(rate)
    y, backed = _samples(data)
    factors = None
    spec = "octave"
    if isinstance(taus, str):
        spec = taus
    else:
        t = _np.asarray(taus, dtype=_np.float64)
        if t.ndim != 1 or not _np.all(_np.isfinite(t)) or _np.any(t <= 0):
            raise ValueError("taus must be 'octave', 'decade', 'all' or positive taus in seconds")
        factors = sorted({int(v) for v in _np.round(t * rate) if v >= 1})
        if not factors:
            raise ValueError("every tau is shorter than half a sample interval" if t.size
                             else "taus is empty: give 'octave', 'decade', 'all' or taus in seconds")
        even_only = kind in _DEV_FACTS and _DEV_FACTS[kind]["even_m_only"]
        odd = [m for m in factors if m % 2] if even_only else []
        if odd and len(odd) == len(factors):
            raise ValueError(f"theo1 needs even averaging factors (m = tau * rate): {odd} odd")
        if odd:
            _warnings.warn(f"theo1 needs even averaging factors (m = tau * rate): {odd} dropped",
                           UserWarning, stacklevel=2)
            factors = [m for m in factors if m % 2 == 0]
    if bias_correction and kind not in _BIAS_CORRECTED:
        raise ValueError(f"bias_correction applies to {_and_list(_BIAS_CORRECTED)} only")
    if alpha is not None and (isinstance(alpha, bool) or kind in _WITHOUT_EDF):
        raise ValueError("alpha is a noise type (2, 1, 0, -1, -2) for the kinds with intervals "
                         f"(not {', '.join(_WITHOUT_EDF)})")
    if alpha is not None and guard:
        raise ValueError("alpha gives every tau one noise type: not with guard")
    if guard and ci is None:
        raise ValueError("guard guards intervals: not with ci=None")
    if alpha is not None and ci is None and not bias_correction:
        raise ValueError("alpha sets the noise type of the bounds and the bias correction: "
                         "with ci=None and no bias_correction it has nothing to set")
    r = _gyroflip._curve(kind, y, rate, input, spec, factors, None if ci is None else float(ci), backed,
                         bool(guard), bool(bias_correction),
                         None if alpha is None else _operator.index(alpha))
    return Deviation(kind=kind, ci=None if kind in _WITHOUT_EDF else ci, **r)


def dynamic_deviation(data, kind="oadev", rate=None, input="rate", window_s=None, step_s=None,
                      taus="octave", ci=0.683):
    """The dynamic deviation (DAVAR; Galleani & Tavella 2009), as `gyroflip adev --dynamic`: the
    curve of statistic `kind` over each window of window_s seconds, one every step_s (default a
    quarter window). Returns a list of dicts with start_s (s from the first sample) and arrays
    m, tau_s, dev, n, ci_lo, ci_hi, edf, alpha: each window's bounds at two-sided level ci from
    the noise type identified in that window and the EDF of its length, as deviation() on the
    window alone (ci=None, or a kind without an EDF: NaN bounds and alpha). window_s and step_s
    are rounded to whole samples (halves up) and refused beyond the series, a step below one
    sample interval too: `adev --dynamic`'s rules, from the library."""
    rate = _positive_rate(rate)
    y, _ = _samples(data)
    if window_s is None:
        raise ValueError("window_s must be a positive number of seconds")
    return _gyroflip._dynamic(kind, y, rate, input, float(window_s),
                              None if step_s is None else float(step_s), taus,
                              None if ci is None else float(ci))


_GYRO_UNITS = {"rate": ("deg/s", "rad/s", "deg/h"), "angle": ("deg", "rad")}
_ACCEL_UNITS = ("m/s^2", "g", "mg", "ug")


def _sensor(column, quantity, units, input):
    """(quantity, unit) of one column: `units` when given, else the unit its name states
    (docs/ANALYSIS.md, "Accelerometers"; ax_mps2, "acc_x [m/s^2]"), else quantity's default
    (deg/s or deg; m/s^2). A contradiction raises ValueError naming the column."""
    named = _gyroflip._unit_of_column(str(column)) if column is not None else None
    if quantity is not None and quantity not in ("gyro", "accel"):
        raise ValueError(f"quantity must be 'gyro' or 'accel' (got {quantity!r})")
    if units is not None:
        q = "accel" if units in _ACCEL_UNITS else "gyro"
        if named is not None and named[0] != q:
            raise ValueError(f"column {column!r} is named in {named[1]}, but units={units!r} is "
                             f"a unit of {'an accelerometer' if q == 'accel' else 'a gyro'}")
    elif named is not None:
        q, units = named
    else:
        q = quantity or "gyro"
        units = "m/s^2" if q == "accel" else ("deg" if input == "angle" else "deg/s")
    if quantity is not None and quantity != q:
        raise ValueError(f"column {column!r} is in {units}, not a unit of quantity={quantity!r}")
    allowed = _ACCEL_UNITS if q == "accel" else _GYRO_UNITS.get(input, ())
    if units not in allowed:
        raise ValueError(f"units must be one of {', '.join(allowed)} for a "
                         f"{'an accelerometer' if q == 'accel' else 'gyro'} {input} (got {units!r})")
    return q, units


def _axes(data, columns=None):
    """The axes of `data` as [(name, 1-D array, file-backed)]: a dict of columns (its keys the
    names), a 2-D array (one axis per column, as np.loadtxt and a CSV give them; more columns
    than rows is refused as a transposed record), or a 1-D array (one axis, `columns` or
    "data")."""
    if isinstance(data, dict):
        return [(str(k), *_samples(v, str(k))) for k, v in data.items()]
    a = data if isinstance(data, _np.ndarray) else _np.asarray(data, dtype=_np.float64)
    if a.ndim == 2:
        if a.shape[1] > a.shape[0]:
            raise ValueError(f"data has {a.shape[1]} columns and {a.shape[0]} rows: give one axis "
                             "per column (transpose it: data.T)")
        names = list(columns) if columns is not None else [f"axis{k}" for k in range(a.shape[1])]
        if len(names) != a.shape[1]:
            raise ValueError(f"columns names {len(names)} axes, data has {a.shape[1]}")
        return [(str(n), *_samples(_np.ascontiguousarray(a[:, k]), str(n))) for k, n in enumerate(names)]
    y, backed = _samples(data)
    return [(str(columns) if isinstance(columns, str) else "data", y, backed)]


def noise(data, rate, input="rate", units=None, ci=0.683, fit_taus=None, abba_cycles=False,
          name="<array>", column=None, quantity=None):
    """The IEEE 952 noise terms of a static gyro or accelerometer record, fitted to its OADEV (as
    `gyroflip noise`).

    data: 1-D samples at `rate` Hz; or several axes: a dict {name: samples} or a 2-D array with
      one axis per column (then one result per axis: a dict by name, or a list in column order).
      input="rate" or "angle". `rate` has no default: a default of 1 Hz silently made every term
      of a 100 Hz record wrong (ARW 10x), so it must be given.
    By default the short taus a low-pass (anti-alias) filter or a spectral line shaped are left
    out of the fit ("short_taus_left_out"); fit_taus fits a range as given.
    quantity: "gyro" or "accel"; default from each column's name (its unit: ax_mps2,
      "acc_x [m/s^2]", gx_dps; docs/ANALYSIS.md "Accelerometers"), else gyro.
    units: the samples' unit: a gyro's "deg/s" (default for a rate), "rad/s", "deg/h"; "deg"
      (default for an angle) or "rad"; an accelerometer's "m/s^2" (default), "g", "mg", "ug".
      Gyro terms are reported in degree units and in radians, an accelerometer's in m/s^2 units
      and g units (vrw_mps2_rthz, bias_instability_mg, acceleration_rw_mps3_rthz, ...).
    ci: confidence level of the intervals. fit_taus: (lo, hi) in seconds, the taus fitted.
    abba_cycles: the data are the cycle values of gyroflip's abba pairing (correlated
      neighbours; the white-noise term is modelled accordingly).
    column: the name of a 1-D record's column (its unit may say what it is); for a 2-D array,
      the columns' names.
    Returns a dict with the keys of `gyroflip noise --json`: arw_dps_rthz, arw_deg_rth,
    bias_instability_deg_h, rrw_deg_h_rth, quantization_deg, rate_ramp_deg_h2, ... Each resolved
    term has KEY_lo and KEY_hi; an unresolved one is None with KEY_upper, its upper limit. Also
    the OADEV points ("oadev"), the misfit points and the slope read-offs ("readoffs")."""
    rate = _positive_rate(rate)
    axes = _axes(data, column)
    lo, hi = (0.0, float("inf")) if fit_taus is None else (float(fit_taus[0]), float(fit_taus[1]))
    out = []
    for col, y, backed in axes:
        q, u = _sensor(col if (column is not None or len(axes) > 1 or isinstance(data, dict)) else None,
                       quantity, units, input)
        out.append(_gyroflip._noise(y, rate, input, u, q, float(ci), lo, hi, bool(abba_cycles),
                                    str(name), col, backed))
    if isinstance(data, dict):
        return {col: r for (col, _, _), r in zip(axes, out)}
    if len(axes) > 1 or (isinstance(data, _np.ndarray) and data.ndim == 2):
        return out
    return out[0]


def plot(data, rate, path, units=None, quantity=None, plot_units=None, title=None, ci=0.683,
         fit_taus=None, long_taus=False, input="rate", column=None):
    """The noise figure of `gyroflip noise --plot` (docs/ANALYSIS.md, "The figure"): each axis's
    Allan curve with its bounds, the fitted term lines and read-off marks, drawn by gnuplot to
    `path` (.png, .svg or .pdf; its .gp script and data beside it). data, rate, units, quantity,
    ci, fit_taus, input, column: as noise(). plot_units: "deg/h" (gyro default), "deg/s",
    "rad/s"; "mg" (accelerometer default), "ug", "m/s^2". Gyro and accelerometer axes together
    make two figures: the gyro's at `path`, the accelerometer's at STEM_accel.EXT beside it.
    long_taus: also the points up to m <= (N-1)/2, drawn open, never fitted.
    Returns the noise() results, one per axis (a dict by name for a dict, else a list)."""
    rate = _positive_rate(rate)
    axes = _axes(data, column)
    lo, hi = (0.0, float("inf")) if fit_taus is None else (float(fit_taus[0]), float(fit_taus[1]))
    sensors = [_sensor(col if (column is not None or len(axes) > 1 or isinstance(data, dict)) else None,
                       quantity, units, input) for col, _, _ in axes]
    out = _gyroflip._noise_plot([y for _, y, _ in axes], [c for c, _, _ in axes],
                                [u for _, u in sensors], [q for q, _ in sensors], rate, input,
                                float(ci), lo, hi, bool(long_taus), _os.fspath(path),
                                "" if plot_units is None else str(plot_units),
                                "" if title is None else str(title))
    if isinstance(data, dict):
        return {c: r for (c, _, _), r in zip(axes, out)}
    return list(out)


def _results_list(results):
    """noise() results as a list: one result (a dict with "schema"), a dict by name, or a list."""
    if isinstance(results, dict):
        return [results] if "schema" in results else list(results.values())
    return list(results)


def _kalibr_axes(results, keys, want):
    """[(column, N, N resolved, K, K resolved)] of noise() results in Kalibr's units, the JSON
    keys `keys` = (N key, K key); each result must be of sensor `want`."""
    axes = []
    for r in results:
        if r.get("quantity", "gyro") != want:
            raise ValueError(f"column {r.get('column')!r} is {r.get('quantity')} data, given as {want}")

        def term(key):
            if r.get(key) is None:
                return float(r[key + "_upper"]), False
            return float(r[key]), True
        n, nr = term(keys[0])
        k, kr = term(keys[1])
        axes.append((str(r.get("column", "data")), n, nr, k, kr))
    return axes


def write_kalibr(path, gyro, accel, rostopic="/imu0", rate=None):
    """Writes Kalibr's IMU noise file (as `gyroflip noise --kalibr`; docs/ANALYSIS.md, "Kalibr"):
    rostopic, update_rate, accelerometer_noise_density, accelerometer_random_walk,
    gyroscope_noise_density, gyroscope_random_walk, continuous-time densities in Kalibr's units
    (m/s^2/sqrt(Hz), m/s^3/sqrt(Hz), rad/s/sqrt(Hz), rad/s^2/sqrt(Hz)), not inflated; each the
    largest axis (an unresolved term as its upper limit), every axis as a comment.
    gyro, accel: noise() results of the gyro's and the accelerometer's axes (one, a list or a
    dict). rate: the update rate (Hz); default: the results' own, which must agree.
    Returns the file's text; the file is written atomically (temp + fsync + rename)."""
    gyro, accel = _results_list(gyro), _results_list(accel)
    g = _kalibr_axes(gyro, ("arw_rad_s_rthz", "rrw_rad_s2_rthz"), "gyro")
    a = _kalibr_axes(accel, ("vrw_mps2_rthz", "acceleration_rw_mps3_rthz"), "accel")
    rates = {round(1.0 / r["tau0_s"], 9) for r in gyro + accel}
    if rate is None:
        if len(rates) != 1:
            raise ValueError(f"the axes were sampled at different rates ({sorted(rates)} Hz): Kalibr "
                             "has one update_rate")
        rate = rates.pop()
    rate = _positive_rate(rate)

    def source(rs):
        return ", ".join(sorted({str(r.get("file", "<array>")) for r in rs}))
    return _gyroflip._write_kalibr(_os.fspath(path), str(rostopic), rate, g, a, source(gyro),
                                   source(accel))


@_dataclass(frozen=True)
class Imu:
    """An IMU record as read_imu() reads it: columns {name: 1-D float64 array}, units {name:
    unit}, quantity {name: "gyro" or "accel"}, rate_hz (samples per second), time_s (the time
    stamps in s, or None), path."""
    path: str
    rate_hz: float
    time_s: object
    columns: dict
    units: dict
    quantity: dict

    def noise(self, **kwargs):
        """noise() of every column, with its unit and sensor: a dict by name."""
        return {c: noise(y, self.rate_hz, units=self.units[c], quantity=self.quantity[c],
                         name=self.path, column=c, **kwargs) for c, y in self.columns.items()}


_TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}


def read_imu(path, rate=None, time_column=None, time_unit=None, columns=None, units=None,
             quantity=None, delimiter=None, decimal="."):
    """Reads an IMU CSV file: a header line of column names (lines starting with # skipped), one
    row per sample. Returns an Imu: every numeric column but the time stamps (or `columns`), each
    column's unit and sensor by the rule of noise() (its name's unit, else `units`/`quantity`, else
    deg/s gyro), and the rate.
    rate (Hz): given, or from the time stamps: `time_column` (default: time_s, else t, time,
      timestamp, stamp) in `time_unit` (default: from the name's suffix _s, _ms, _us, _ns, else
      s). Refused: no time stamps and no rate; stamps that go back or jump (a gap larger than
      1.5 sample periods; `gyroflip noise --gaps split` handles gaps).
    delimiter: , ; tab or space (default: detected from the header); decimal: "." or ",".
    Errors: ValueError naming the file, line and column."""
    path = _os.fspath(path)
    with open(path, "r", encoding="utf-8") as f:
        lines = [(k + 1, ln.rstrip("\r\n")) for k, ln in enumerate(f)]
    lines = [(k, ln) for k, ln in lines if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise ValueError(f"{path}: no header line")
    header_line, header = lines[0]
    if delimiter is None:
        delimiter = next((d for d in (",", ";", "\t") if d in header), " ")
    elif delimiter == "tab":
        delimiter = "\t"
    elif delimiter == "space":
        delimiter = " "
    split = (lambda ln: ln.split()) if delimiter == " " else (lambda ln: [c.strip() for c in ln.split(delimiter)])
    names = split(header)
    rows = []
    for k, ln in lines[1:]:
        fields = split(ln)
        if len(fields) != len(names):
            raise ValueError(f"{path}:{k}: {len(fields)} fields, the header has {len(names)}")
        rows.append((k, fields))
    if len(rows) < 2:
        raise ValueError(f"{path}: fewer than 2 rows of data")

    def number(k, c, text):
        try:
            v = float(text.replace(decimal, ".") if decimal != "." else text)
        except ValueError:
            raise ValueError(f"{path}:{k}: column {c + 1} ({names[c]}): not a number: {text!r}") from None
        if not _np.isfinite(v):
            raise ValueError(f"{path}:{k}: column {c + 1} ({names[c]}): not finite: {text!r}")
        return v

    if time_column is None:
        time_column = next((n for n in ("time_s", "t", "time", "timestamp", "stamp", "stamp_ns")
                            if n in names), None)
    elif time_column not in names:
        raise ValueError(f"{path}:{header_line}: no time column {time_column!r} (the header has "
                         f"{', '.join(names)})")
    time_s = None
    if time_column is not None:
        if time_unit is None:
            time_unit = next((u for u in ("ms", "us", "ns", "s") if time_column.endswith("_" + u)), "s")
        if time_unit not in _TIME_UNITS:
            raise ValueError(f"time_unit must be s, ms, us or ns (got {time_unit!r})")
        c = names.index(time_column)
        # Integer stamps (epoch ns) exactly: relative to the first, then scaled.
        raw = [r[c] for _, r in rows]
        if all(t.lstrip("-").isdigit() for t in raw):
            t0 = int(raw[0])
            time_s = _np.array([(int(t) - t0) for t in raw], dtype=_np.float64) * _TIME_UNITS[time_unit]
        else:
            time_s = _np.array([number(k, c, r[c]) for k, r in rows]) * _TIME_UNITS[time_unit]
            time_s = time_s - time_s[0]
        dt = _np.diff(time_s)
        period = float(_np.median(dt))
        if not period > 0.0:
            raise ValueError(f"{path}: column {time_column}: the time stamps do not increase")
        bad = _np.flatnonzero((dt <= 0.0) | (dt > 1.5 * period))
        if bad.size:
            k = rows[int(bad[0]) + 1][0]
            raise ValueError(f"{path}:{k}: column {time_column}: the time stamp "
                             f"{'goes back' if dt[bad[0]] <= 0 else 'jumps'} ({dt[bad[0]]:g} s after "
                             f"the previous, the period is {period:g} s)")
        if rate is None:
            rate = 1.0 / period
    if rate is None:
        raise ValueError(f"{path}: no time column (time_s, t, time, timestamp, stamp): give rate=Hz")
    rate = _positive_rate(rate)
    wanted = list(columns) if columns is not None else [n for n in names if n != time_column]
    cols, unit_of, sensor_of = {}, {}, {}
    for n in wanted:
        if n not in names:
            raise ValueError(f"{path}:{header_line}: no column {n!r} (the header has {', '.join(names)})")
        c = names.index(n)
        if columns is None:
            try:
                float(rows[0][1][c].replace(decimal, "."))
            except ValueError:
                continue  # a text column (a label): not a record
        cols[n] = _np.array([number(k, c, r[c]) for k, r in rows], dtype=_np.float64)
        q, u = _sensor(n, quantity, units, "rate")
        unit_of[n], sensor_of[n] = u, q
    return Imu(path, rate, time_s, cols, unit_of, sensor_of)


def _columns(time_s, angle_deg, rate_dps, temp_c, n_avg, positions_deg=None):
    def col(a, name):
        return None if a is None else _samples(a, name)[0]
    return _gyroflip._Columns(col(time_s, "time_s"), col(angle_deg, "angle_deg"),
                              col(rate_dps, "rate_dps"), col(temp_c, "temp_c"), col(n_avg, "n_avg"),
                              col(positions_deg, "positions_deg"))


def calibrate(time_s, angle_deg, rate_dps, temp_c=None, n_avg=None, latitude=None, axis=None,
              pairing="abba", angle_tolerance_deg=0.0, sensor=None, strict=False,
              table_axis=None, positions_deg=None):
    """Calibrates dN on a stationary flipping recording (paper eqns 8-11), as `gyroflip calibrate`.

    time_s, angle_deg, rate_dps: one value per row (a dwell mean, or a conversion): time (s),
      table angle 0 or 180 deg (NaN while turning; encoder angles within angle_tolerance_deg
      of a position count as it), gyro output (deg/s). temp_c (degC) and n_avg (conversions
      averaged in the row, its weight) are optional.
    latitude (deg) and axis ("north", "east", "up", "down", or "N,E,D"): split dN into its Earth
      term and g-term (paper eqns 9-10). pairing: "abba" (cancels linear drift) or "simple"
      (the paper's).
    sensor: a preset name or TOML preset file whose g-sensitivity specification the stationarity
      test checks the g-term against (default: not checked). strict: raise ValueError for a run
      that fails the stationarity test instead of warning (as `calibrate --strict`).
    Returns the dict `gyroflip calibrate --json` prints (delta_n_dps, stderr_correlated_dps,
    cycles, temp_c, earth_rate_dps, g_term_dps, files[0]["stationarity"], ...) plus "warnings"
    and "cycle_values": arrays time_s, rate_dps (r, paper eqn 7), bias_dps (c), temp_c. Pass the
    dict to compensate(calibration=...).
    pairing="harmonic" (three or more positions, issue 33): also "terms" (b, c1, s1[, c2, s2]:
    name, value_dps, stderr_correlated_dps), "terms_covariance" (row-major lists, (deg/s)^2) and
    "separability" (what each term holds, which pairs no run separates), as `gyroflip calibrate
    --pairing harmonic --json`; table_axis ("up", "down", or as simulate's) names the table's axis
    for that report (default: not recorded, taken as horizontal). positions_deg: the table's
    angles (read_recording's "positions_deg"; default the paper's 0 and 180)."""
    c = _columns(time_s, angle_deg, rate_dps, temp_c, n_avg, positions_deg)
    return _gyroflip._calibrate(c, None if latitude is None else float(latitude), axis, pairing,
                                float(angle_tolerance_deg), None if sensor is None else str(sensor),
                                bool(strict), None if table_axis is None else str(table_axis))


def _int_arg(name, value, lo, hi):
    """`value` as an int in lo..hi; a float, str or bool is refused (never truncated or parsed)."""
    if isinstance(value, bool) or not isinstance(value, _numbers.Integral):
        raise TypeError(f"{name} must be an int, not {type(value).__name__} ({value!r})")
    value = int(value)
    if not lo <= value <= hi:
        raise ValueError(f"{name} must be an int in {lo}..{hi} (got {value})")
    return value


def _real_arg(name, value):
    """`value` as a float; a str or bool is refused (the library checks finiteness and range)."""
    if isinstance(value, bool) or not isinstance(value, _numbers.Real):
        raise TypeError(f"{name} must be a real number, not {type(value).__name__} ({value!r})")
    return float(value)


def _path_arg(name, value):
    if not isinstance(value, (str, _os.PathLike)):
        raise TypeError(f"{name} must be a path (str or os.PathLike), not {type(value).__name__}")
    return _os.fspath(value)


def _paths_arg(name, files):
    """A list or tuple of paths. A single path is refused rather than wrapped: a str is also a
    sequence, and the provenance must show the call as made (docs/python.md)."""
    if isinstance(files, (str, bytes, _os.PathLike)):
        raise TypeError(f"{name} must be a list or tuple of paths, not a single path "
                        f"(write [{_os.fspath(files)!r}])")
    if not isinstance(files, (list, tuple)):
        raise TypeError(f"{name} must be a list or tuple of paths, not {type(files).__name__}")
    return [_path_arg(f"{name}[{k}]", f) for k, f in enumerate(files)]


def calibrate_runs(files, latitude=None, axis=None, pairing="abba", degree=None,
                   angle_tolerance_deg=0.0, sensor=None, strict=False):
    """Calibrates dN on stationary recordings (CSV or .gfr), as `gyroflip calibrate FILE... --json`
    (the same library call): each run's dN (paper eqns 8-11), all cycles pooled, and with several
    files a dN model (a line over a temperature span of 2 degC or more, else the runs' weighted
    mean; `degree` chooses the polynomial's degree).

    files: a list or tuple of the recordings' paths (a single path is refused: write [path]), one
      stationary run each, of one sensor.
    latitude (deg) and axis: split dN into its Earth term and g-term (paper eqns 9-10).
    pairing: "abba" (default) or "simple" (the paper's). angle_tolerance_deg: as calibrate().
    degree: an int in 0..6 (as `--degree`). A wrong type raises TypeError naming the argument.
    sensor, strict: as calibrate() (`--sensor`, `--strict`); the default specification is the
      recordings' built-in preset.
    Returns the dict `gyroflip calibrate --json` prints (schema gyroflip.calibration/5: delta_n_dps,
    stderr_correlated_dps, files (each with its "stationarity"), model, uncertainty, sensor, ...)
    plus "warnings". The top-level delta_n_dps is all cycles pooled (a summary); the dN that
    compensate() and report() apply is "model"'s (the runs' random-effects fit:
    model["coeffs_dps"][0] for runs at one temperature); "uncertainty" says what to quote
    (new_power_up_dps). Each of "files"
    names its file's sha256, size_bytes and origin ("simulated", "emulated", "rig", "unknown").
    The warnings are what the command prints as
    warnings: a rig setting that differs between files, a sensor nobody named, a damaged .gfr
    region skipped). Pass it to compensate(calibration=...); report() takes a calibration file's
    path instead (write the dict with json.dump, or use `gyroflip calibrate -o CAL.json`).
    Releases the GIL; Ctrl-C stops it."""
    paths = _paths_arg("files", files)
    return _gyroflip._calibrate_runs(paths, None if latitude is None else _real_arg("latitude", latitude),
                                     axis, pairing, None if degree is None else _int_arg("degree", degree, 0, 6),
                                     _real_arg("angle_tolerance_deg", angle_tolerance_deg),
                                     None if sensor is None else str(sensor), bool(strict))


def compensate(time_s, angle_deg, rate_dps, temp_c=None, n_avg=None, calibration=None,
               delta_n_dps=None, pairing=None, drift_window_s=100.0, angle_tolerance_deg=0.0,
               strict=False, positions_deg=None):
    """Compensates a flipping recording (paper eqn 12), as `gyroflip compensate`.

    The columns as for calibrate(). calibration: a calibrate() result, or the path of a
    calibration file (`gyroflip calibrate -o CAL.json`); its dN(T) model is used when it has one
    (then temp_c is needed). Or delta_n_dps: a constant dN (deg/s). pairing: default the
    calibration's (else "abba"). drift_window_s: the moving-mean window of the drift figure.
    Returns a dict of arrays, one per cycle: time_s, rate_dps (the input rate w_in), bias_dps
    (the bias the flip removed), temp_c, delta_n_dps (what was subtracted); and "summary", the
    object `gyroflip compensate --json` prints (schema gyroflip.compensate/2: cycles, mean_dps,
    std_dps, stderr_dps, stderr_correlated_dps, drift_dps, delta_n, ...), and "warnings": a
    calibration made of a run that failed the stationarity test (its dN is not the sensor's), or
    of runs never tested (a file from before the test). strict=True raises ValueError for the
    first instead (as `gyroflip compensate --strict`).
    A calibration of the harmonic scheme (issue 33: calibrate(..., pairing="harmonic")) is applied
    as `gyroflip compensate --calibration` applies it: on a run of three or more positions
    (positions_deg: the table's angles, read_recording's "positions_deg"; default the paper's 0
    and 180) its terms other than c1 are removed at each position and each period's c1 loses the
    calibration's; on a 0/180 pair at theta the dN is c1 cos theta + s1 sin theta, its error from
    the terms' covariance. "applied" then says which (as the CLI's note)."""
    text = None
    if calibration is not None:
        if isinstance(calibration, dict):
            text = _json.dumps({k: v for k, v in calibration.items()
                                if k not in ("cycle_values", "warnings")})
        else:
            with open(_os.fspath(calibration), "rb") as f:
                text = f.read().decode("utf-8", errors="replace")
    c = _columns(time_s, angle_deg, rate_dps, temp_c, n_avg, positions_deg)
    return _gyroflip._compensate(c, None if delta_n_dps is None else float(delta_n_dps), text, pairing,
                                 float(drift_window_s), float(angle_tolerance_deg), bool(strict))


def simulate(sensor, duration_s=3600.0, seed=1, latitude=42.6, axis="north", n_avg=256,
             settle_s=0.08, temp=None, rate="0", power_on_before_s=0.0, flip=True,
             positions=(0.0, 180.0), order="auto", azimuth=None, table_axis=None, tilt_mrad=0.0,
             tilt_azimuth=0.0):
    """Simulates the rig (as `gyroflip simulate`): the sensor on the stepper turntable, read by
    the AD7739, flipped 0/180 deg, one row per dwell (n_avg conversions averaged).

    sensor: a preset ("adxrs150", "hz1-90-100a", ...; `gyroflip sensors`) or a TOML preset file.
    temp: degC as a number, or a profile spec ("ramp:20:4:9000", ...); default the preset's
      reference temperature. rate: the input-rate profile spec ("0", "0.25", "step:...").
    power_on_before_s: sensor on this long before t = 0 (0: a cold start, warm-up drift).
    As `simulate`'s options of the same names (issue 33): positions: the table's angles (2 to 8,
    deg, whole steps); order: "auto" (two: A, B; more: the sweep), "sweep" or "cycle";
    azimuth: the sensitive axis's azimuth at the table's 0 deg (deg from north, clockwise;
    instead of axis; north finding: table_axis="up"); table_axis: the turntable's axis (None: the
    horizontal default); tilt_mrad, tilt_azimuth: the table axis's lean and its direction.
    Returns a dict of arrays time_s, angle_deg, rate_dps, temp_c, n_avg and the truth
    bias_dps, g_term_dps, earth_dps, input_dps (as seen at each row's orientation); and
    delta_n_truth_dps (Earth + g-term at 0 deg at the start temperature) and sensor."""
    return _gyroflip._simulate(str(sensor), float(duration_s), int(seed), float(latitude), str(axis),
                               int(n_avg), float(settle_s), None if temp is None else str(temp),
                               str(rate), float(power_on_before_s), bool(flip),
                               [float(a) for a in positions], str(order),
                               None if azimuth is None else float(azimuth),
                               "" if table_axis is None else str(table_axis), float(tilt_mrad),
                               float(tilt_azimuth))


def read_recording(path, angle_tolerance_deg=0.0):
    """Reads a recording: gyroflip's CSV format (docs/FORMATS.md) or a rig recording (.gfr).
    Returns a dict of arrays time_s, angle_deg (NaN while turning), rate_dps, temp_c (NaN when
    absent), n_avg, position (each row's index into positions_deg, -1 while turning) and
    positions_deg (the recording's table: its `# positions_deg:` line, a .gfr's configuration, or
    the distinct angles; docs/FORMATS.md); "metadata" (the `# key: value` lines; a .gfr's META)
    and "warnings".
    Errors name FILE:LINE:COL (CSV) or the record (.gfr)."""
    return _gyroflip._read_recording(_os.fspath(path), float(angle_tolerance_deg))


def _call_text(name, args, kwargs):
    """The call as written, for a report's provenance: gyroflip.NAME(args, key=value, ...)."""
    words = [repr(a) for a in args] + [f"{k}={v!r}" for k, v in kwargs.items()]
    return f"python3: gyroflip.{name}({', '.join(words)})"


def plan(dead_time, sensor=None, static=None, rate=None, units="deg/s", duration=3600.0,
         min_dwell=0.01, max_dwell=None, positions=None, heading=False, latitude=None,
         order="auto"):
    """The dwell and flip period that minimise a run's error for a dead time (as `gyroflip plan`).

    dead_time: seconds lost per turn (turn + settle). The noise comes from either `sensor` (a
    preset name such as "adxrs150", or a TOML preset file) or `static`: 1-D rate samples of the
    sensor at rest at `rate` Hz in `units` ("deg/s", "rad/s", "deg/h"), whose IEEE 952 fit over
    the taus from `min_dwell` on is used. duration: the run's length (s). Returns a dict with the
    keys of `gyroflip plan --json`: dwell_s, period_s, predicted_sigma_dps,
    sigma_without_dead_time_dps, conversions_per_dwell, closed_form, reference_dwell (the
    paper's 0.512 s), by_dwell and by_duration (lists of points), notes. docs/PLANNER.md.
    positions: the table's angles (deg; three or more: an indexed run in the sweep, planned for
    the first harmonic's error). heading=True with latitude (deg): plan for north finding
    (positions default 0, 90, 180, 270); the dict then has "heading" (predicted_sigma_deg,
    sigma_deg_rth, white_limit_deg, by_dwell, by_duration), as `plan --heading --latitude`.
    order: the visiting order planned for, as `plan --order` ("auto", "sweep", "cycle",
    "there-and-back"; three or more positions: the dict's "order" and "visiting_order_deg")."""
    data = None if static is None else _samples(static, "static")[0]
    if data is not None:
        rate = _positive_rate(rate)
    if bool(heading) != (latitude is not None):
        raise ValueError("plan: heading=True and latitude go together")
    return _gyroflip._plan(sensor, data, None if rate is None else float(rate), str(units),
                           float(dead_time), float(duration), float(min_dwell),
                           0.0 if max_dwell is None else float(max_dwell),
                           [] if positions is None else [float(a) for a in positions],
                           float(latitude) if heading else None, str(order))


def sensors(dead_time=0.4, latitude=42.6):
    """The built-in sensor presets (as `gyroflip sensors --json`): the dict with "sensors", one
    entry per preset with "name", "description", "params" (each parameter's value, unit, what,
    source, min, max) and "implied": what its noise implies for a dead time per turn (s) at a
    latitude (deg): the corner time "corner_tau_s", the best dwell "dwell_s" = sqrt(d tau_c), the
    flip run's error and the heading limits per sqrt(hour) (docs/PLANNER.md, docs/NORTH.md)."""
    return _gyroflip._sensors(float(dead_time), float(latitude))


def separability(positions, table_axis=None):
    """What a table of positions separates, before a run (as `gyroflip calibrate --explain
    --positions A,B,... [--table-axis AXIS] --json`, issue 33): the estimable terms, what each holds
    physically and every pair no run of that table separates (docs/METHOD-NOTES.md, "N-position
    indexing"). positions: the angles (deg); table_axis: "up", "down" or as simulate's (default:
    horizontal, the paper's rig)."""
    return _gyroflip._separability([float(a) for a in positions],
                                   "" if table_axis is None else str(table_axis))


def heading(runs, latitude, table_axis=None, base_turn=None, sensor=None, harmonics=1):
    """North finding (as `gyroflip heading`): the azimuth (deg from north, clockwise) of the
    sensitive axis at the table's 0 deg from indexed runs about a vertical table axis (>= 3
    positions; docs/NORTH.md), with its 1 sigma from the data's own noise.

    runs: a list of one recording's path, or two with the rig's base turned between them (the
      table's tilt x g-sensitivity term, which reads exactly as Earth rate, is then removed).
    latitude: the site's (deg). table_axis: "up" or "down" (default: the recordings', else up).
    base_turn: two runs: the base's clockwise turn (deg) from the first to the second (default:
      from the recordings' azimuths). sensor: a preset or TOML file for the dead-time bound.
    Returns the dict of `gyroflip heading --json`: heading_deg, sigma_deg, limit_deg,
    ratio_to_limit, arw_dps_rthz, scheme, dead_time_bound_deg, runs, caveats, ...
    A 0/180 run (scale factor known): the heading up to its sign (heading_mirror_deg,
    ambiguous). harmonics=2 also fits the second harmonic (>= 5 positions; docs/NORTH.md)."""
    paths = _paths_arg("runs", runs)
    return _gyroflip._heading(paths, float(latitude), None if table_axis is None else str(table_axis),
                              None if base_turn is None else float(base_turn),
                              None if sensor is None else str(sensor), int(harmonics))


def report(files, output, latitude=None, axis=None, calibration=None, title=None, pairing="abba",
           expected_rate=None, sensor=None):
    """Writes the report folder `gyroflip report FILE... -o OUTPUT` writes (the same library call,
    docs/REPORT.md): index.html (tables, figures, provenance), report.pdf, summary.json and
    figures/ with each figure's gnuplot script and data. Needs gnuplot and Chromium or pdfunite.

    files: a list or tuple of the recordings' paths (CSV or .gfr; a single path is refused: write
      [path]). Without `calibration` they are stationary calibration runs (each calibrated;
      dN(T) over a temperature span); with it (a CAL.json path: the page lists the file with its
      SHA-256, so a calibrate_runs() dict must be written to a file first) each is compensated
      with its dN or dN(T).
    output: the report folder: new, empty, or one a report made (nothing of the user's is ever
      replaced; docs/cli.md, "report").
    latitude (deg) and axis: split dN into its Earth term and g-term. title: the page's title
      (default: one naming the sensor and the runs). pairing: "abba" or "simple".
    expected_rate (deg/s, with calibration): the rate a rate table commanded; each run's error
      and scale-factor error against it (0, a run at rest: the error only).
    sensor: a built-in preset's name or a TOML preset file, as `report --sensor`: the
      specification the runs' g-term is checked against and whose spread the budget takes
      (default: a simulated run's own sensor model, else the built-in preset it names).
    Returns summary.json as a dict (schema gyroflip.report/N: the numbers per run, the dN budget,
    the conclusion and "warnings"). The provenance names this call. Releases the GIL; Ctrl-C
    stops it."""
    paths = _paths_arg("files", files)
    output = _path_arg("output", output)
    if isinstance(calibration, dict):
        raise TypeError("calibration must be the path of a calibration file (gyroflip calibrate -o "
                        "CAL.json, or a calibrate_runs() dict written with json.dump), not a dict: "
                        "the report lists it with its SHA-256")
    calibration = None if calibration is None else _path_arg("calibration", calibration)
    latitude = None if latitude is None else _real_arg("latitude", latitude)
    expected_rate = None if expected_rate is None else _real_arg("expected_rate", expected_rate)
    kwargs = {k: v for k, v in (("latitude", latitude), ("axis", axis), ("calibration", calibration),
                                ("title", title), ("expected_rate", expected_rate),
                                ("sensor", sensor)) if v is not None}
    if pairing != "abba":
        kwargs["pairing"] = pairing
    command = _call_text("report", [files, output], kwargs)
    # What to do next with calibration runs, in Python's words (the CLI gives its commands).
    next_step = ""
    if calibration is None:
        cal_kwargs = {k: v for k, v in (("latitude", latitude), ("axis", axis)) if v is not None}
        if pairing != "abba":
            cal_kwargs["pairing"] = pairing
        next_step = (f"Next: cal = {_call_text('calibrate_runs', [list(paths)], cal_kwargs)[9:]}, "
                     "json.dump(cal, open('cal.json', 'w')), then gyroflip.compensate(..., "
                     "calibration=cal).")
    return _gyroflip._report(paths, output, latitude, axis, "" if calibration is None else calibration,
                             "" if title is None else str(title), pairing, expected_rate, command,
                             next_step, None if sensor is None else str(sensor))


def reproduce(quick=False, seed=1, campaigns=None, output=None, sensors=None):
    """The paper's experiment on the simulator, as `gyroflip reproduce` (the same library call,
    docs/REPRODUCE.md): the campaigns of Tab. 3/4 and the runs of Figs 3-10 on every core, set
    beside the paper's numbers.

    quick: one campaign of runs a quarter as long. seed: the first campaign's seed, an int in
      0..2**64-1. campaigns: how many campaigns, an int in 1..1000 (default 10, 1 with quick).
      output: a report folder for the page, its figures and summary.json (as `-o DIR`), or None.
      sensors: a dict {NAME: FILE.toml} (as `--sensor NAME=FILE.toml`): put a sensor model to
      the paper's tests instead of the preset NAME ("adxrs150" or "hz1-90-100a"); nothing of it
      was fitted here, so its tables and per-cycle noise are tests of it.
    A float, str or bool where an int is expected raises TypeError, an int out of range
    ValueError, each naming the argument (never truncated or parsed); a sensor name that is not
    one of the paper's raises ValueError, a TOML file that cannot be read or parsed an error
    naming its file, line and column.
    Returns summary.json as a dict (schema gyroflip.reproduce/N) plus "text", the comparison the
    command prints. Releases the GIL; Ctrl-C stops it."""
    if not isinstance(quick, bool):
        raise TypeError(f"quick must be a bool, not {type(quick).__name__} ({quick!r})")
    seed = _int_arg("seed", seed, 0, 2**64 - 1)
    campaigns = None if campaigns is None else _int_arg("campaigns", campaigns, 1, 1000)
    output = None if output is None else _path_arg("output", output)
    if sensors is None:
        sensors = {}
    if not isinstance(sensors, dict):
        raise TypeError("sensors must be a dict {name: TOML file}, e.g. {'hz1-90-100a': "
                        f"'my_hz1.toml'}}, not {type(sensors).__name__}")
    files = []
    for name, path in sensors.items():
        if not isinstance(name, str):
            raise TypeError(f"sensors: a name must be a str, not {type(name).__name__} ({name!r})")
        files.append((name, _path_arg(f"sensors[{name!r}]", path)))
    kwargs = {k: v for k, v in (("quick", quick), ("seed", seed), ("campaigns", campaigns),
                                ("output", output)) if v is not None and v is not False and not (k == "seed" and v == 1)}
    if files:
        kwargs["sensors"] = dict(files)
    command = _call_text("reproduce", [], kwargs)
    return _gyroflip._reproduce(bool(quick), seed, campaigns, "" if output is None else output,
                                files, command)
