"""`import gyroflip.allantools as allantools`: the public names of allantools 2024.06 (and the
newer PSD helpers), computed by gyroflip's C++ core; nothing is passed to allantools, which need
not be installed, nor scipy. docs/python.md, "The allantools drop-in", lists the names and where
they differ from allantools. gyroflip's own module (`import gyroflip`) keeps its strict rules
(finite input, ValueError)."""

from . import allantools, ci, mask, noise
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
    "tdev_realtime", "mask", "RateError", "NoValidTau",
]
