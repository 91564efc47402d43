"""The Allan family from Python against published values: NIST SP1065's NBS14 sets, the
Stable32 tables in tests/vectors/stable32 (deviations to 1e-4 relative, as the C++ tests; term
counts exactly; 68.3 % bounds to 3e-3), and allantools' conventions (its tau list, n, errs)."""
import os

import numpy as np
import pytest

import gyroflip
from conftest import read_stable32, read_values

KINDS = ["adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev"]

# NIST SP1065 p. 107-108: the NBS14 9-value frequency set, tau = 1 and 2.
NBS14 = [892, 809, 823, 798, 671, 644, 883, 903, 677]
NBS14_EXPECT = {
    "adev": (91.22945, 115.8082), "oadev": (91.22945, 85.95287), "mdev": (91.22945, 74.78849),
    "totdev": (91.22945, 93.90379), "hdev": (70.80608, 116.7980), "ohdev": (70.80607, 85.61487),
    "tdev": (52.67135, 86.35831),
}


def nbs14_1000():
    """SP1065's 1000-point set: n <- 16807 n mod (2^31 - 1) from 1234567890, divided by 2^31 - 1."""
    y, n = [], 1234567890
    for _ in range(1000):
        y.append(n / 2147483647.0)
        n = (16807 * n) % 2147483647
    return np.array(y)


NBS14_1000_EXPECT = {
    "adev": (0.2922319, 0.09965736, 0.03897804), "oadev": (0.2922319, 0.09159953, 0.03241343),
    "mdev": (0.2922319, 0.06172376, 0.02170921), "totdev": (0.2922319, 0.09134743, 0.03406530),
    "hdev": (0.2943883, 0.1052754, 0.03910860), "ohdev": (0.2943883, 0.09581083, 0.03237638),
    "tdev": (0.1687202, 0.3563623, 1.253382),
}


@pytest.mark.parametrize("kind", KINDS)
def test_nbs14_nine_points_compat(kind):
    taus, devs, errs, ns = getattr(gyroflip, kind)(NBS14, rate=1.0, data_type="freq", taus=[1, 2])
    assert list(taus) == [1.0, 2.0]
    np.testing.assert_allclose(devs, NBS14_EXPECT[kind], rtol=1e-6)
    np.testing.assert_allclose(errs, devs / np.sqrt(ns))


@pytest.mark.parametrize("kind", KINDS)
def test_nbs14_thousand_points(kind):
    d = gyroflip.deviation(nbs14_1000(), kind, rate=1.0, input="rate", taus=[1, 10, 100], ci=None)
    np.testing.assert_allclose(d.dev, NBS14_1000_EXPECT[kind], rtol=1e-6)
    assert np.all(np.isnan(d.ci_lo))


@pytest.mark.parametrize("kind", KINDS)
def test_phase_dat_octave_with_bounds(kind, vectors):
    x = np.array(read_values(os.path.join(vectors, "stable32/phasedat/PHASE.DAT")))
    rows = read_stable32(os.path.join(vectors, f"stable32/phasedat/phase_dat_{kind}_octave.txt"))
    d = gyroflip.deviation(x, kind, rate=1.0, input="angle", taus="octave", ci=0.683)
    assert list(d.m) == [r[0] for r in rows]
    assert list(d.n) == [r[2] for r in rows]
    np.testing.assert_allclose(d.dev, [r[5] for r in rows], rtol=1e-4)
    assert np.all((d.ci_lo < d.dev) & (d.dev < d.ci_hi))
    # End to end, noise identification included, as the C++ test does: Stable32's bounds to 1e-3
    # wherever the identified noise type is Stable32's (issue 23; all but m = 128, where B1 on 8
    # points reads flicker PM). guard=True keeps the white-FM EDF there too.
    same = d.alpha == np.array([r[3] for r in rows])
    assert np.count_nonzero(same) >= 7
    np.testing.assert_allclose(d.ci_lo[same], np.array([r[4] for r in rows])[same], rtol=1e-3)
    np.testing.assert_allclose(d.ci_hi[same], np.array([r[6] for r in rows])[same], rtol=1e-3)
    g = gyroflip.deviation(x, kind, rate=1.0, input="angle", taus="octave", ci=0.683, guard=True)
    assert np.all(g.edf <= d.edf)
    if kind == "oadev":
        np.testing.assert_allclose(g.ci_lo, [r[4] for r in rows], rtol=1e-3)
        np.testing.assert_allclose(g.ci_hi, [r[6] for r in rows], rtol=1e-3)


@pytest.mark.parametrize("kind", KINDS)
def test_phase_dat_all_tau_compat(kind, vectors):
    """allantools' taus="all" on phase data: every m with n > 1, the same values as Stable32
    where its all-tau table has the point."""
    x = np.array(read_values(os.path.join(vectors, "stable32/phasedat/PHASE.DAT")))
    rows = read_stable32(os.path.join(vectors, f"stable32/phasedat/phase_dat_{kind}.txt"))
    taus, devs, errs, ns = getattr(gyroflip, kind)(x, rate=1.0, taus="all")
    assert taus[0] == 1.0 and np.all(np.diff(taus) == 1.0)
    assert np.all(ns > 1)
    by_m = {int(t): (d, n) for t, d, n in zip(taus, devs, ns)}
    for af, _, n, _, _, sigma, _ in rows:
        d, nn = by_m[af]
        assert nn == n, af
        assert d == pytest.approx(sigma, rel=1e-4), af


def test_pink_frequency_octave_with_tau0_1s(vectors):
    y = np.array(read_values(os.path.join(vectors, "stable32/pink_frequency/pink_frequency.txt")))
    rows = read_stable32(os.path.join(vectors, "stable32/pink_frequency/s32_oadev_octave.txt"))
    d = gyroflip.deviation(y, "oadev", rate=1.0, input="rate", ci=0.683)
    assert list(d.n) == [r[2] for r in rows]
    np.testing.assert_allclose(d.dev, [r[5] for r in rows], rtol=1e-4)
    # The lag-1 noise type is Stable32's wherever 30 decimated points or more remain.
    enough = (len(y) // d.m) >= 30
    assert list(d.alpha[enough]) == [r[3] for r, e in zip(rows, enough) if e]


def test_allantools_tau_rules():
    """allantools' conventions: octave taus 1, 2, 4 ... up to len(phase), ns as its loops count
    them (ADEV floor((N-1)/m) - 1, OADEV N - 2m, MDEV N - 3m + 1, OHDEV N - 3m, TOTDEV N - 2),
    points with ns <= 1 dropped, freq data integrated to N + 1 phase points."""
    rng = np.random.default_rng(7)
    y = rng.normal(size=100)
    n_phase = 101
    t, d, e, n = gyroflip.oadev(y, rate=2.0, data_type="freq")
    m = np.round(t * 2.0)
    assert list(m) == [1, 2, 4, 8, 16, 32]  # m = 64 leaves 101 - 128 < 2 terms
    np.testing.assert_array_equal(n, n_phase - 2 * m)
    _, _, _, n = gyroflip.adev(y, rate=2.0, data_type="freq")
    np.testing.assert_array_equal(n, [(n_phase - 1) // k - 1 for k in [1, 2, 4, 8, 16, 32]])
    _, _, _, n = gyroflip.mdev(y, rate=2.0, data_type="freq")
    np.testing.assert_array_equal(n, [n_phase - 3 * k + 1 for k in [1, 2, 4, 8, 16, 32]])
    _, _, _, n = gyroflip.ohdev(y, rate=2.0, data_type="freq")
    np.testing.assert_array_equal(n, [n_phase - 3 * k for k in [1, 2, 4, 8, 16, 32]])
    t, _, _, n = gyroflip.totdev(y, rate=2.0, data_type="freq")
    assert list(np.round(t * 2.0)) == [1, 2, 4, 8, 16, 32, 64]
    assert np.all(n == n_phase - 2)
    # Taus given in seconds round to the nearest factor, half to even (numpy.round: 2.5 -> 2,
    # 3.5 -> 4), duplicates merged.
    t, _, _, _ = gyroflip.oadev(y, rate=2.0, data_type="freq", taus=[0.5, 1.25, 1.75, 3.0, 3.1])
    assert list(t) == [0.5, 1.0, 2.0, 3.0]
    # "decade" is 1, 2, 4, 10, 20, 40, ... as in allantools.
    t, _, _, _ = gyroflip.oadev(np.arange(1000.0), data_type="phase", taus="decade", rate=1.0)
    assert list(t) == [1, 2, 4, 10, 20, 40, 100, 200, 400]


def test_phase_is_the_default_data_type():
    """allantools reads data as phase unless told; a rate series read as phase is its integral's
    derivative, so the two differ (the reason deviation() takes input= explicitly)."""
    y = np.random.default_rng(3).normal(size=4096)
    phase = np.concatenate([[0.0], np.cumsum(y)])
    t1, d1, _, _ = gyroflip.oadev(phase, rate=1.0)
    t2, d2, _, _ = gyroflip.oadev(y, data_type="freq", rate=1.0)
    np.testing.assert_allclose(d1, d2, rtol=1e-9)
    _, d3, _, _ = gyroflip.oadev(y, rate=1.0)
    assert not np.allclose(d3, d2[: len(d3)])


def test_other_dtypes_and_lists_convert():
    y = np.random.default_rng(5).normal(size=1000)
    _, d64, _, _ = gyroflip.oadev(y, data_type="freq", rate=1.0)
    _, dl, _, _ = gyroflip.oadev(list(y), data_type="freq", rate=1.0)
    _, d32, _, _ = gyroflip.oadev(y.astype(np.float32), data_type="freq", rate=1.0)
    _, ds, _, _ = gyroflip.oadev(y[::1].copy(order="C")[::-1][::-1], data_type="freq", rate=1.0)
    np.testing.assert_array_equal(d64, dl)
    np.testing.assert_array_equal(d64, ds)
    np.testing.assert_allclose(d64, d32, rtol=1e-6)


def test_help_is_useful():
    doc = gyroflip.oadev.__doc__
    assert "SP1065 eqn 11" in doc and "(taus, devs, errs, ns)" in doc and "deg/s" in doc
    assert "ci_lo" in gyroflip.deviation.__doc__ or "bounds" in gyroflip.deviation.__doc__


# Issue 23: the total and time-error statistics against Stable32's PHASE.DAT tables, through the
# allantools-compatible functions (taus m / rate, ns as Stable32's "#") and deviation().
EXTENDED_TABLES = [
    ("mtotdev", "phase_dat_mtotdev_octave.txt"), ("ttotdev", "phase_dat_ttotdev_octave.txt"),
    ("htotdev", "phase_dat_htotdev_octave_nobias.txt"), ("theo1", "phase_dat_theo1_alpha0.txt"),
    ("mtie", "phase_dat_mtie.txt"), ("tierms", "phase_dat_tierms.txt"),
]


def read_rows_any(path):
    """(af, n, sigma) of a Stable32 table, `#`-commented data rows included."""
    out = []
    with open(path) as f:
        for line in f:
            t = line.lstrip("# ").split()
            if len(t) in (4, 7) and t[0].isdigit():
                out.append((int(t[0]), float(t[2]), float(t[5] if len(t) == 7 else t[3])))
    return out


@pytest.mark.parametrize("kind,table", EXTENDED_TABLES)
def test_extended_kinds_match_stable32(kind, table, vectors):
    x = np.array(read_values(os.path.join(vectors, "stable32/phasedat/PHASE.DAT")))
    rows = read_rows_any(os.path.join(vectors, "stable32/phasedat", table))
    taus, devs, errs, ns = getattr(gyroflip, kind)(x, rate=1.0, taus=[r[0] for r in rows])
    assert list(taus) == [float(r[0]) for r in rows]
    np.testing.assert_allclose(devs, [r[2] for r in rows], rtol=1e-4)
    np.testing.assert_allclose(ns, [r[1] for r in rows], rtol=5e-5)  # Theo1's "#" has 5 digits
    d = gyroflip.deviation(x, kind, rate=1.0, input="angle", taus=[r[0] for r in rows])
    np.testing.assert_allclose(d.dev, devs, rtol=1e-12)
    if kind == "theo1":
        np.testing.assert_allclose(d.tau_s, 0.75 * taus)


def read_rows_ci(path):
    """(af, alpha, lo, sigma, hi) of a Stable32 table with bounds, `#`-commented rows included."""
    out = []
    with open(path) as f:
        for line in f:
            t = line.lstrip("# ").split()
            if len(t) == 7 and t[0].isdigit():
                out.append((int(t[0]), int(t[3]), float(t[4]), float(t[5]), float(t[6])))
    return out


@pytest.mark.parametrize("kind,table,bias", [
    ("mtotdev", "phase_dat_mtotdev_octave.txt", False),
    ("mtotdev", "phase_dat_mtotdev_decade.txt", False),
    ("ttotdev", "phase_dat_ttotdev_octave.txt", False),
    ("htotdev", "phase_dat_htotdev_octave.txt", True),
])
def test_total_family_bounds_as_stable32(kind, table, bias, vectors):
    """Issue 23: deviation()'s bounds of the total family are Stable32's to 1e-3 wherever the
    identified noise type is its own (every row here), but HTOTDEV with flicker PM (m = 128, 256;
    docs/ANALYSIS.md, "Intervals of the total family")."""
    x = np.array(read_values(os.path.join(vectors, "stable32/phasedat/PHASE.DAT")))
    rows = read_rows_ci(os.path.join(vectors, "stable32/phasedat", table))
    d = gyroflip.deviation(x, kind, rate=1.0, input="angle", taus=[r[0] for r in rows], ci=0.683,
                           bias_correction=bias)
    np.testing.assert_array_equal(d.alpha, [r[1] for r in rows])
    keep = ~((d.alpha == 1) & (kind == "htotdev"))
    assert np.count_nonzero(keep) >= 7
    np.testing.assert_allclose(d.dev, [r[3] for r in rows], rtol=1e-4)
    np.testing.assert_allclose(d.ci_lo[keep], np.array([r[2] for r in rows])[keep], rtol=1e-3)
    np.testing.assert_allclose(d.ci_hi[keep], np.array([r[4] for r in rows])[keep], rtol=1e-3)


def test_htotdev_bias_correction_matches_stable32(vectors):
    x = np.array(read_values(os.path.join(vectors, "stable32/phasedat/PHASE.DAT")))
    rows = read_rows_any(os.path.join(vectors, "stable32/phasedat/phase_dat_htotdev_octave.txt"))
    d = gyroflip.deviation(x, "htotdev", rate=1.0, input="angle", taus=[r[0] for r in rows],
                           bias_correction=True)
    np.testing.assert_allclose(d.dev, [r[2] for r in rows], rtol=1e-4)
    with pytest.raises(ValueError):
        gyroflip.deviation(x, "oadev", input="angle", bias_correction=True, rate=1.0)



# Review E-L6: the published bias-corrected values of the 1000-point set (SP1065; Riley, "The
# calculation of time domain frequency stability"; docs/FACTS.md §6) are white-FM corrected at every
# tau. At tau = 100 the type read is flicker PM (as in Stable32's tables), so they need alpha=0.
def test_published_bias_corrected_values_need_white_fm():
    f = np.array(nbs14_1000())
    for kind, published in (("htotdev", 0.03058103), ("mtotdev", 0.02287774),
                            ("ttotdev", 1.320847)):
        read = gyroflip.deviation(f, kind, taus=[100.0], bias_correction=True, ci=None, rate=1.0)
        given = gyroflip.deviation(f, kind, taus=[100.0], bias_correction=True, ci=None, alpha=0, rate=1.0)
        assert read.alpha[0] == 1 and given.alpha[0] == 0
        assert abs(given.dev[0] / published - 1.0) < 1e-6, kind
        assert abs(read.dev[0] / published - 1.0) > 2e-3, kind

# Re-review N-H1 / L6: with the type identified, MTOTDEV's bias-corrected value at AF 170 takes the
# type carried from the nearest shorter listed tau (Stable32's rule); alpha=0 gives every list
# Stable32's all-tau value 1.3547e-02 (alpha 0).
def test_given_alpha_makes_a_tau_independent_of_the_list(vectors):
    x = np.array(read_values(os.path.join(vectors, "stable32/phasedat/PHASE.DAT")))
    carried = gyroflip.deviation(x, "mtotdev", input="angle", taus=[100.0, 170.0],
                                 bias_correction=True, rate=1.0)
    assert carried.alpha[-1] == 1
    for taus in ([170.0], [100.0, 170.0], [10.0, 170.0, 180.0]):
        d = gyroflip.deviation(x, "mtotdev", input="angle", taus=taus, bias_correction=True,
                               alpha=0, rate=1.0)
        i = list(d.m).index(170)
        assert d.alpha[i] == 0
        assert abs(d.dev[i] / 1.3547e-02 - 1.0) < 1e-4
    with pytest.raises(ValueError):
        gyroflip.deviation(x, "oadev", input="angle", alpha=3, rate=1.0)
    with pytest.raises(ValueError):
        gyroflip.deviation(x, "oadev", input="angle", alpha=0, guard=True, rate=1.0)
