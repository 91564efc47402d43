"""Noise generators of `gyroflip.allantools` (allantools' noise module): white, brown (random walk),
violet, pink (Voss-McCartney), a one-sided PSD estimate and Timmer & Koenig's synthesis from a
piecewise power-law PSD. NumPy's global random generator, as allantools."""

import math

import numpy as np


def numpy_psd(x, f_sample=1.0):
    """One-sided PSD of x: (frequencies 0..f_sample/2, 2 |rfft|^2 / (N f_sample))."""
    p = 2.0 / (len(x) * f_sample) * np.abs(np.fft.rfft(x)) ** 2
    return np.linspace(0, f_sample / 2.0, len(p)), p


def scipy_psd(x, f_sample=1.0, nr_segments=4):
    """Welch's PSD (needs scipy, which gyroflip does not install)."""
    import scipy.signal  # pylint: disable=import-outside-toplevel
    return scipy.signal.welch(x, f_sample, nperseg=len(x) / nr_segments)


def white(num_points=1024, b0=1.0, fs=1.0):
    """White noise of one-sided PSD b0 up to fs/2."""
    return math.sqrt(b0 * fs / 2.0) * np.random.randn(num_points)


def brown(num_points=1024, b_minus2=1.0, fs=1.0):
    """Random walk of PSD b_minus2 f^-2: integrated white noise."""
    return np.cumsum(white(num_points, b0=b_minus2 * 4.0 * math.pi ** 2, fs=fs)) / float(fs)


def violet(num_points=1024, b2=1, fs=1):
    """Violet noise of PSD b2 f^2: differentiated white noise."""
    return float(fs) * np.diff(white(num_points + 1, b0=b2 / (2.0 * math.pi) ** 2, fs=fs))


def iterpink(depth=20):
    """An endless sequence of pink (1/f) samples by the Voss-McCartney scheme: `depth` white
    sources, source c replaced every 2^c samples."""
    values = np.random.randn(depth)
    smooth = np.random.randn(depth)
    source = np.random.randn(depth)
    total = values.sum()
    i = 0
    while True:
        yield total + smooth[i]
        i += 1
        if i == depth:
            i = 0
            smooth = np.random.randn(depth)
            source = np.random.randn(depth)
            continue
        c = (i & -i).bit_length() - 1  # trailing zeros of i
        total += source[i] - values[c]
        values[c] = source[i]


def pink(num_points=1024, depth=80):
    """num_points pink samples (iterpink)."""
    g = iterpink(depth)
    return np.array([next(g) for _ in range(num_points)])


def timmer_koenig_from_psd(f_nodes, h, alpha, duration, timestep, output="phase", seed=None):
    """Timmer & Koenig (1995) synthesis of int(duration/timestep) samples whose fractional-
    frequency PSD is h_i f^alpha_i between the breaks f_nodes (none for one segment): Gaussian
    complex coefficients of standard deviation sqrt(S_x)/2 on the grid f1 = 1/((n-1) dt) .. 1/(2dt),
    Hermitian, inverse FFT scaled by sqrt((n-1)/dt). output 'phase' (x) or 'freq' (dx/dt)."""
    f_nodes = np.asarray(f_nodes, dtype=float)
    h = np.atleast_1d(np.asarray(h, dtype=float))
    alpha = np.atleast_1d(np.asarray(alpha, dtype=float))
    if duration <= 0 or timestep <= 0:
        raise ValueError("duration and timestep must be positive")
    if h.size != alpha.size:
        raise ValueError("h and alpha must have the same length")
    if h.size == 1:
        f_nodes = np.array([])
    if f_nodes.size not in (0, h.size - 1):
        raise ValueError("f_nodes must have len(h) - 1 breaks (or none for one segment)")
    if seed is not None:
        np.random.seed(int(seed))
    n = int(duration / timestep)
    if n < 4:
        raise ValueError("duration/timestep gives fewer than 4 samples")
    freq = np.linspace(1.0 / ((n - 1) * timestep), 1.0 / (2.0 * timestep), n // 2 + 1)
    seg = np.searchsorted(f_nodes, freq, side="right") if f_nodes.size else np.zeros(freq.size, int)
    seg = np.minimum(seg, h.size - 1)
    sy = h[seg] * freq ** alpha[seg]
    sx = sy / (2.0 * np.pi * freq) ** 2
    sx[0] = 0.0
    spec = np.zeros(n, dtype=complex)
    for j in range(1, n // 2 + 1):
        spec[j] = np.sqrt(sx[j]) / 2.0 * (np.random.normal(0, 1) + 1j * np.random.normal(0, 1))
    spec[n // 2 + 1:] = np.conj(spec[1:n // 2][::-1])
    x = (np.fft.ifft(spec) * np.sqrt((n - 1) / timestep)).real
    if output == "phase":
        return x
    if output == "freq":
        return np.concatenate(([0.0], np.diff(x) / timestep))
    raise ValueError("output must be 'phase' or 'freq'")
