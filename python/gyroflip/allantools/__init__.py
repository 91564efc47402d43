"""`import gyroflip.allantools as allantools`: the public names of allantools 2024.06 (and the
newer PSD helpers), computed by gyroflip's C++ core; nothing is passed to allantools, which need
not be installed, nor scipy. docs/python.md, "The allantools drop-in", lists the names and where
they differ from allantools. gyroflip's own module (`import gyroflip`) keeps its strict rules
(finite input, ValueError, no default rate).

`gyroflip.allantools.install()` registers this package as `allantools` in sys.modules, with every
submodule allantools has (allantools.allantools, .ci, .dataset, .mask, .noise, .noise_kasdin,
.plot, .realtime), so that code written for allantools (`import allantools`,
`import allantools.ci as ci`, `from allantools import noise`) runs unchanged."""

import sys as _sys

from . import allantools, ci, dataset, mask, noise, noise_kasdin, plot, realtime
from .allantools import (NoValidTau, RateError, __version__, adev, adev2psd_piecewise_approx,
                         calc_hdev_phase, calc_htotdev_freq, calc_mtotdev_phase, frequency2fractional,
                         frequency2phase, gcodev, gradev, hdev, htotdev, input_to_phase, mdev, mtie,
                         mtie_phase_fast, mtotdev, oadev, ohdev, pdev, phase2frequency, phase2radians,
                         psd2allan, psd_piecewise_to_adev, remove_small_ns, tau_generator,
                         tau_reduction, tdev, theo1, three_cornered_hat_phase, tierms, totdev,
                         trim_data, ttotdev)
from .ci import (autocorr_noise_id, b1_noise_id, confidence_interval, confidence_interval_noiseID,
                 edf_greenhall, edf_mtotdev, edf_simple, edf_totdev)
from .dataset import Dataset
from .noise_kasdin import Noise
from .plot import Plot
from .realtime import oadev_realtime, ohdev_realtime, tdev_realtime

__all__ = [
    "__version__", "adev", "oadev", "mdev", "pdev", "hdev", "ohdev", "calc_hdev_phase", "tdev",
    "totdev", "mtotdev", "calc_mtotdev_phase", "ttotdev", "htotdev", "calc_htotdev_freq", "theo1",
    "mtie", "mtie_phase_fast", "tierms", "frequency2phase", "phase2frequency", "phase2radians",
    "frequency2fractional", "three_cornered_hat_phase", "noise", "gradev", "gcodev", "trim_data",
    "edf_simple", "edf_greenhall", "edf_totdev", "edf_mtotdev", "confidence_interval",
    "confidence_interval_noiseID", "autocorr_noise_id", "b1_noise_id", "Dataset", "Noise", "Plot",
    "psd2allan", "adev2psd_piecewise_approx", "psd_piecewise_to_adev", "tau_generator",
    "tau_reduction", "remove_small_ns", "input_to_phase", "oadev_realtime", "ohdev_realtime",
    "tdev_realtime", "mask", "RateError", "NoValidTau", "install", "SUBMODULES",
]

#: allantools' submodules (its package layout: allantools/{allantools,ci,dataset,mask,noise,
#: noise_kasdin,plot,realtime}.py), each registered by install().
SUBMODULES = ("allantools", "ci", "dataset", "mask", "noise", "noise_kasdin", "plot", "realtime")


def install(replace=False):
    """Makes `import allantools` (and `import allantools.ci`, `from allantools.allantools import
    oadev`, ...) load this package: registers it as "allantools" in sys.modules with every
    submodule as "allantools.<name>". An allantools already imported (the real one) is left in
    place and RuntimeError raised, unless replace=True: code must not silently mix the two.
    Returns this module."""
    this = _sys.modules[__name__]
    present = _sys.modules.get("allantools")
    if present is not None and present is not this and not replace:
        raise RuntimeError("another allantools is already imported (" +
                           str(getattr(present, "__file__", present)) +
                           "): install(replace=True) to use gyroflip's in its place")
    _sys.modules["allantools"] = this
    for name in SUBMODULES:
        _sys.modules["allantools." + name] = _sys.modules[__name__ + "." + name]
    return this
