"""Shared fixtures of the Python module's tests: where the module, the CLI and the reference
vectors are (CTest passes them in the environment; tests/CMakeLists.txt)."""
import os
import sys

import pytest

sys.path.insert(0, os.environ["GYROFLIP_PYTHON_DIR"])

VECTORS = os.environ["GYROFLIP_VECTORS_DIR"]
EXE = os.environ["GYROFLIP_EXE"]


def read_values(path):
    """The numbers of a data file, one per line, '#' lines skipped."""
    with open(path) as f:
        return [float(line.split()[0]) for line in f if line.strip() and not line.startswith("#")]


def read_stable32(path):
    """Rows (af, tau, n, alpha, lo, sigma, hi) of a Stable32 table."""
    rows = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.lstrip().startswith("#"):
                af, tau, n, alpha, lo, sigma, hi = line.split()[:7]
                rows.append((int(af), float(tau), int(n), int(alpha), float(lo), float(sigma), float(hi)))
    return rows


@pytest.fixture
def vectors():
    return VECTORS


@pytest.fixture
def exe():
    return EXE
