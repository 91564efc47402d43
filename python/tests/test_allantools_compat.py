"""gyroflip.allantools runs code written for allantools 2024.06 (issue 23, section 3): each test
states a behaviour from allantools' documentation (its docstrings and README) and checks it, and
the numbers against Stable32 and the NBS14 published values. allantools itself is never imported
(it is not installed); neither are scipy nor matplotlib."""
import os
import sys
import warnings

import numpy as np
import pytest

import gyroflip.allantools as at
from conftest import read_stable32, read_values

NBS14_PHASE = [0.00000, 103.11111, 123.22222, 157.33333, 166.44444, 48.55555, -96.33333,
               -2.22222, 111.88889, 0.00000]
NBS14_FREQ = [892.0, 809.0, 823.0, 798.0, 671.0, 644.0, 883.0, 903.0, 677.0]


def test_every_public_name_is_there_and_nothing_heavy_is_imported():
    for name in ["adev", "oadev", "mdev", "pdev", "hdev", "ohdev", "calc_hdev_phase", "tdev",
                 "totdev", "mtotdev", "calc_mtotdev_phase", "ttotdev", "htotdev",
                 "calc_htotdev_freq", "theo1", "mtie", "mtie_phase_fast", "tierms",
                 "frequency2phase", "phase2frequency", "phase2radians", "frequency2fractional",
                 "three_cornered_hat_phase", "noise", "gradev", "gcodev", "trim_data",
                 "edf_simple", "edf_greenhall", "edf_totdev", "edf_mtotdev", "confidence_interval",
                 "confidence_interval_noiseID", "autocorr_noise_id", "b1_noise_id", "Dataset",
                 "Noise", "Plot", "psd2allan", "adev2psd_piecewise_approx", "psd_piecewise_to_adev",
                 "tau_generator", "tau_reduction", "remove_small_ns", "oadev_realtime",
                 "ohdev_realtime", "tdev_realtime", "mask", "__version__"]:
        assert hasattr(at, name), name
    assert at.allantools.tau_reduction is at.tau_reduction  # at.allantools.X works too
    assert "allantools" not in [m.split(".")[0] for m in sys.modules]
    assert "scipy" not in sys.modules and "matplotlib" not in sys.modules


# -- tau_generator (allantools docs: "all" 1..len, "octave" 1, 2, 4, ..., "decade" 1, 2, 4, 10, ...)
D128 = np.random.default_rng(1).random(128)


@pytest.mark.parametrize("taus,expected", [
    (None, [1, 2, 4, 8, 16, 32]), ([], [1, 2, 4, 8, 16, 32]), ("octave", [1, 2, 4, 8, 16, 32]),
    ("all", list(range(1, 43))), ("decade", [1, 2, 4, 10, 20, 40]), ([1, 2, 3, 4], [1, 2, 3, 4]),
    (np.array([1, 2, 3, 4]), [1, 2, 3, 4])])
def test_taus_as_allantools_generates_them(taus, expected):
    t, _, _, _ = at.adev(D128, taus=taus)
    np.testing.assert_allclose(t, expected)


def test_tau_generator_signature_and_tau_reduction():
    data, m, taus = at.tau_generator(D128, 2.0, taus="octave")
    assert np.array_equal(data, D128) and list(m) == [1, 2, 4, 8, 16, 32, 64] and np.allclose(taus, m / 2.0)
    data, _, _ = at.tau_generator([1.0, 2.0, 3.0, 4.0, 5.0], 1.0)
    assert isinstance(data, np.ndarray)  # allantools returns np.array(data)
    _, m, _ = at.tau_generator(D128, 1.0, taus="all", even=True, maximum_m=10)
    assert list(m) == [2, 4, 6, 8, 10]
    ms, _ = at.tau_reduction(np.arange(1, 43), 1.0, 10)
    np.testing.assert_allclose(ms, [1, 2, 3, 4, 5, 7, 8, 11, 14, 17, 22, 28, 35])
    ms, _ = at.tau_reduction(np.arange(1, 43), 1.0, 2)
    np.testing.assert_allclose(ms, [1, 5, 17])


def test_nan_taus_are_dropped_and_float32_taus_give_float32():
    t, d, e, n = at.oadev(D128, taus=np.array([1.0, np.nan, 4.0], dtype=np.float32))
    assert list(t) == [1.0, 4.0]
    assert t.dtype == d.dtype == e.dtype == n.dtype == np.float32


def test_bad_rate_is_both_value_error_and_runtime_error():
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(RuntimeError):
            at.adev(D128, rate=bad)
        with pytest.raises(ValueError):
            at.oadev(D128, rate=bad)


def test_no_valid_tau_is_a_user_warning():
    with pytest.raises(UserWarning):
        at.adev(D128, taus=[1e6])
    with pytest.raises(UserWarning):
        at.remove_small_ns(np.array([1.0]), np.array([1.0]), np.array([1.0]), np.array([1.0]))
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        _, m, _ = at.tau_generator(D128, 1.0, taus=[1e6])
    assert len(m) == 0 and issubclass(w[0].category, UserWarning)


def test_ns_are_at_least_two_for_unreasonable_taus():
    phase = at.noise.white(500)
    for f in (at.adev, at.oadev, at.mdev, at.tdev, at.hdev, at.ohdev, at.totdev, at.mtie, at.tierms,
              at.mtotdev, at.ttotdev, at.htotdev, at.theo1, at.pdev):
        t, d, e, n = f(phase, rate=1.0, taus=list(np.logspace(0, 4, 400)))
        assert len(t) == len(d) == len(e) == len(n) > 0 and np.all(n > 1), f.__name__


def test_remove_small_ns_with_one_or_two_error_arrays():
    taus = np.arange(1.0, 6.0)
    ns = np.array([8.0, 4.0, 2.0, 1.0, 1.0])
    t, d, e, n = at.remove_small_ns(taus, taus * 2, taus * 3, ns)
    assert list(t) == [1, 2, 3] and list(e) == [3, 6, 9]
    t, d, (lo, hi), n = at.remove_small_ns(taus, taus, [taus, -taus], ns)
    assert list(lo) == [1, 2, 3] and list(hi) == [-1, -2, -3]


def test_trim_data_and_nan_in_frequency_data():
    x = np.array([np.nan, np.nan, 1, 2, 3.4, 2.3, np.nan, 9, 12, 45, np.nan])
    np.testing.assert_array_equal(at.trim_data(x), [1, 2, 3.4, 2.3, np.nan, 9, 12, 45])
    np.testing.assert_array_equal(at.trim_data(D128), D128)
    assert at.trim_data([np.nan, 1.0, 2.0, np.nan]) == [1.0, 2.0]  # a list stays a list (allantools slices)
    y = np.random.default_rng(2).normal(size=1000)
    padded = np.concatenate(([np.nan] * 3, y, [np.nan] * 2))
    a = at.oadev(y, data_type="freq")
    b = at.oadev(padded, data_type="freq")
    for u, v in zip(a, b):
        np.testing.assert_array_equal(u, v)
    inside = y.copy()
    inside[500] = np.nan
    t, d, e, n = at.oadev(inside, data_type="freq")
    assert len(t) == len(a[0]) and np.all(np.isnan(d))


def test_column_arrays_are_accepted():
    y = np.random.default_rng(3).normal(size=(300, 1))
    for u, v in zip(at.mdev(y, data_type="freq"), at.mdev(y[:, 0], data_type="freq")):
        np.testing.assert_array_equal(u, v)


def test_nbs14_and_stable32_values_through_allantools_names(vectors):
    # NIST SP1065 p. 107-108 (10-point set), as allantools' own tests use them.
    expect = {"adev": (91.22945, 115.8082), "oadev": (91.22945, 85.95287),
              "mdev": (91.22945, 74.78849), "totdev": (91.22945, 93.90379),
              "hdev": (70.80608, 116.7980), "tdev": (52.67135, 86.35831),
              "ohdev": (70.80607, 85.61487), "mtotdev": (64.509, 64.794), "ttotdev": (37.244, 74.818)}
    for name, (d1, d2) in expect.items():
        for data, kind in ((NBS14_PHASE, "phase"), (NBS14_FREQ, "freq")):
            _, d, _, _ = getattr(at, name)(data, rate=1.0, data_type=kind, taus=[1, 2])
            np.testing.assert_allclose(d, [d1, d2], rtol=1e-4, err_msg=name)
    x = np.array(read_values(os.path.join(vectors, "stable32/phasedat/PHASE.DAT")))
    rows = read_stable32(os.path.join(vectors, "stable32/phasedat/phase_dat_oadev_octave.txt"))
    t, d, e, n = at.oadev(x, taus=[r[0] for r in rows])
    np.testing.assert_allclose(d, [r[5] for r in rows], rtol=1e-4)
    assert list(n) == [r[2] for r in rows]


def test_conversions():
    y = np.array([1.0, 2.0, 4.0])
    x = at.frequency2phase(y, 2.0)
    # Mean removed (7/3), integrated with dt = 1/2, a leading 0: (-4/3, -1/3, 5/3) / 2 summed.
    np.testing.assert_allclose(x, [0, -2 / 3, -5 / 6, 0], atol=1e-15)
    np.testing.assert_allclose(at.phase2frequency([0.0, 1.0, 3.0], 2.0), [2.0, 4.0])
    np.testing.assert_allclose(at.phase2radians([1e-9], 10e6), [2 * np.pi * 1e-2])
    np.testing.assert_allclose(at.frequency2fractional([9.0, 11.0]), [-0.1, 0.1])
    np.testing.assert_allclose(at.frequency2fractional([9.0, 11.0], mean_frequency=9.0), [0, 2 / 9])
    assert isinstance(at.frequency2fractional([9.0, 11.0]), list)  # allantools: a list comprehension
    y32 = y.astype(np.float32)  # allantools' NumPy arithmetic keeps float32
    assert at.frequency2phase(y32, 2.0).dtype == np.float32 and at.phase2frequency(y32, 2.0).dtype == np.float32
    np.testing.assert_allclose(at.frequency2phase(y32, 2.0), x, rtol=1e-6)


def test_confidence_intervals_and_edf():
    lo, hi = at.confidence_interval(1.0, 10.0, ci=0.9)
    # chi-squared 5 % and 95 % points at 10 degrees of freedom: 3.940299, 18.307038.
    np.testing.assert_allclose([lo, hi], [np.sqrt(10 / 18.307038), np.sqrt(10 / 3.940299)], rtol=1e-6)
    assert abs(at.ci.ONE_SIGMA_CI - 0.6826894921370859) < 1e-15
    # scipy's chi2.ppf outside [0, 1] is NaN: allantools' gradev passes (dev, ci, edf) swapped, so
    # a level of 50 gives (NaN, NaN) there (re-review N-L3); a level of 3 folds to quantiles 1
    # and 0: allantools' edf/ppf(0) = inf low, edf/ppf(1) = 0 high.
    assert all(np.isnan(at.confidence_interval(1.0, 0.9, 50)))
    assert at.confidence_interval(1.0, 10.0, 3.0) == (np.inf, 0.0)
    np.testing.assert_allclose(at.edf_simple(1001, 1, 0), (3 * 1000 / 2 - 2 * 999 / 1001) * 4 / 9)
    assert at.edf_simple(100, 2, 7) == 99  # unknown noise: N - 1
    assert at.edf_totdev(1001, 10, 0) == pytest.approx(150.15)
    assert at.edf_mtotdev(1001, 10, 0) == pytest.approx(1.1 * 100.1 - 1.2)
    assert at.edf_greenhall(0, 2, 8, 1001, overlapping=True) == pytest.approx(166.0, rel=1e-3)
    x = np.array(at.noise.white(5000)).cumsum()  # random-walk phase: white FM, alpha 0
    assert at.autocorr_noise_id(x, 1)[0] == 0
    assert at.autocorr_noise_id(at.noise.white(5000), 1)[0] == 2
    lo, hi = at.confidence_interval_noiseID(x, 1.0, 4, dev_type="oadev")
    assert lo < 1.0 < hi


def test_realtime_equals_batch_on_nbs14():
    o = at.oadev_realtime(afs=[1, 2], tau0=1.0)
    h = at.ohdev_realtime(afs=[1, 2], tau0=1.0)
    t = at.tdev_realtime(afs=[1, 2], tau0=1.0)
    for v in NBS14_PHASE:
        o.add_phase(v)
        h.add_phase(v)
        t.add_phase(v)
    np.testing.assert_allclose(o.dev, [91.22945, 85.95287], rtol=1e-6)
    np.testing.assert_allclose(h.dev, [70.80607, 85.61487], rtol=1e-6)
    np.testing.assert_allclose(t.mdev(), [91.22945, 74.78849], rtol=1e-6)
    f = at.oadev_realtime(afs=[1], auto_afs=True)
    for v in NBS14_FREQ:
        f.add_frequency(v)
    assert len(f.x) == 10 and list(f.taus()[:2]) == [1, 2]


def test_noise_generators():
    np.random.seed(5)
    w = at.noise.white(2 ** 16, b0=2.0, fs=4.0)
    f, p = at.noise.numpy_psd(w, 4.0)
    assert abs(np.mean(p[1:]) / 2.0 - 1) < 0.05  # PSD b0 up to fs/2
    assert len(at.noise.brown(100)) == 100 and len(at.noise.violet(100)) == 100
    assert len(at.noise.pink(100)) == 100
    n = at.Noise(nr=2 ** 12, qd=1e-20, b=-2)
    n.generateNoise()
    assert n.time_series.shape == (2 ** 12,)
    # White FM (b = -2) as Kasdin-Walter phase: ADEV follows the predicted prefactor.
    _, d, _, _ = at.oadev(n.time_series, taus=[16.0])
    assert d[0] == pytest.approx(n.adev(1.0, 16.0), rel=0.2)
    x = at.noise.timmer_koenig_from_psd(np.array([]), [1e-22], [0.0], 4096.0, 1.0, seed=42)
    assert x.shape == (4096,)


def test_gradev_gcodev_and_three_cornered_hat():
    rng = np.random.default_rng(7)
    y = rng.normal(size=5000).cumsum()
    gap = y.copy()
    gap[2000:2300] = np.nan
    t, d, (lo, hi), n = at.gradev(y, taus=[1, 4, 16])
    tg, dg, _, ng = at.gradev(gap, taus=[1, 4, 16])
    assert np.all(np.abs(np.log(d / dg)) < 0.2) and np.all(ng < n)
    assert np.all(lo > 0) and np.all(hi > 0)
    a, b, c = rng.normal(size=(3, 20000))
    t, g, _, _ = at.gcodev(a - b, c - b, data_type="freq", taus=[1.0])
    assert g[0] == pytest.approx(1.0, rel=0.05)  # B's white FM at tau = 1
    t, da, ea, na = at.three_cornered_hat_phase(at.frequency2phase(a - b, 1), at.frequency2phase(b - 2 * c, 1),
                                                at.frequency2phase(2 * c - a, 1), 1.0, [1.0], at.oadev)
    assert da[0] == pytest.approx(1.0, rel=0.05)


def test_dataset_and_plot(tmp_path):
    ds = at.Dataset(data=NBS14_PHASE, rate=1.0, data_type="phase", taus=[1, 2])
    r = ds.compute("oadev")
    np.testing.assert_allclose(r["stat"], [91.22945, 85.95287], rtol=1e-6)
    assert ds.out["stat_id"] == "oadev"
    ds.write_results(str(tmp_path / "r.txt"))
    assert "oadev" in (tmp_path / "r.txt").read_text()
    with pytest.raises(RuntimeError):
        ds.compute("trim_data")
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        pytest.skip("matplotlib is not installed (not a gyroflip dependency)")
    p = at.Plot(no_display=True)
    p.plot(ds, errorbars=True, grid=True)
    p.save(str(tmp_path / "p.png"))


def test_masks():
    assert at.mask.prc_tdev(10) == 3e-9 and at.mask.prc_tdev(1e4) == 30e-9
    assert at.mask.prc_mtie(100) == pytest.approx(1e-6 * (0.0275 + 0.025))
    assert at.mask.eprtc_mtie(1e6) == 30e-9 and at.mask.prtcB_mtie(100) == 40e-9


def test_psd_conversions():
    taus = np.geomspace(1.0, 1e4, 9)
    a = 1e-13
    f_nodes, _, h, alpha = at.adev2psd_piecewise_approx(a * taus ** -0.5, taus)
    assert h.size == 1 and abs(alpha[0]) < 1e-9 and h[0] == pytest.approx(2 * a * a, rel=1e-8)
    f_nodes, _, h, alpha = at.adev2psd_piecewise_approx(np.full_like(taus, a), taus)
    assert alpha[0] == pytest.approx(-1.0) and h[0] == pytest.approx(a * a / (2 * np.log(2)), rel=1e-8)
    back = at.psd_piecewise_to_adev(h, alpha, f_nodes, taus)
    np.testing.assert_allclose(back, a, rtol=1e-6)
    t = np.geomspace(1, 1e4, 5)
    with pytest.raises(ValueError):
        at.adev2psd_piecewise_approx(1e-13 * t ** -1.5, t)
    _, _, h, alpha = at.adev2psd_piecewise_approx(1e-13 * t ** 1.5, t, vartype="hdev")
    assert alpha[0] == pytest.approx(-4.0)
    tt = np.array([1, 10, 1e2, 1e3, 5e3, 1e4])
    ad = np.array([1e-11, 2e-11, 5.5e-11, 1.3e-10, 2.85e-10, 4e-10])
    f_nodes, _, h, alpha = at.adev2psd_piecewise_approx(ad, tt)
    np.testing.assert_allclose(at.psd_piecewise_to_adev(h, alpha, f_nodes, tt), ad, rtol=0.15)
    # psd2allan: a flat one-sided S_y = h0 (white FM) gives ADEV sqrt(h0 / (2 tau)).
    taus2, ad2 = at.psd2allan(np.full(20001, 2e-20), 0.001)
    mid = (taus2 > 1) & (taus2 < 100)
    np.testing.assert_allclose(ad2[mid], np.sqrt(2e-20 / (2 * taus2[mid])), rtol=0.05)


def test_total_family_errors_and_counts_as_allantools():
    """allantools 2024.06's mtotdev, ttotdev and htotdev return errs = devs / sqrt(ns) (its own
    docstrings call them rough estimates; no EDF) with ns the number of terms: N - 3m + 1 for
    MTOTDEV and TTOTDEV on N phase points, Nf - 3m + 1 for HTOTDEV on Nf frequency points (OHDEV's
    N - 3m at m = 1); taus only up to a third of the points. edf_mtotdev stays SP1065 Table 8."""
    x = np.cumsum(np.random.default_rng(7).normal(size=1001))  # white FM phase
    n = len(x)
    for f in (at.mtotdev, at.ttotdev):
        t, d, e, ns = f(x, rate=1.0, taus="octave")
        np.testing.assert_array_equal(ns, n - 3 * t + 1)
        np.testing.assert_allclose(e, d / np.sqrt(ns), rtol=1e-15)
        assert t.max() <= n / 3
    t, d, e, ns = at.htotdev(x, rate=1.0, taus="octave")
    nf = n - 1
    np.testing.assert_array_equal(ns, np.where(t == 1, n - 3, nf - 3 * t + 1))
    np.testing.assert_allclose(e, d / np.sqrt(ns), rtol=1e-15)
    assert t.max() <= nf / 3
    _, td, te, tn = at.ttotdev(x, rate=1.0, taus=[4.0])
    _, md, _, _ = at.mtotdev(x, rate=1.0, taus=[4.0])
    np.testing.assert_allclose(td, 4.0 * md / np.sqrt(3.0), rtol=1e-12)
    assert at.edf_mtotdev(1001, 100, 1) == pytest.approx(1.2 * 10.01 - 1.4)


def test_b1_noise_id_names_each_power_law_noise_at_any_rate():
    """Kasdin-Walter noise of phase-PSD exponent b (alpha = b + 2) from the module's own Noise, 2^14
    points: the B1 ratio (with R(n) for PM) names alpha 2, 1, 0, -1, -2 at af = 16, whatever the
    sample rate (B1 and R(n) are ratios of variances at the same tau)."""
    for seed in (0, 1):
        for b in (0, -1, -2, -3, -4):
            np.random.seed(seed)
            n = at.Noise(2 ** 14, 1e-20, b)
            n.generateNoise()
            x = n.time_series
            for rate in (1.0, 10.0, 0.1):
                assert at.b1_noise_id(x, 16, rate) == b + 2, (seed, b, rate)
            assert at.ci.b1(x, 16, 10.0) == pytest.approx(at.ci.b1(x, 16, 1.0), rel=1e-9)
    # White FM: B1 = 1 (SP1065 section 5.5.6), within its scatter for 1024 averages.
    np.random.seed(0)
    x = np.cumsum(np.random.normal(size=2 ** 14))
    assert at.ci.b1(x, 16, 1.0) == pytest.approx(1.0, abs=0.1)


def test_too_short_data_raise_no_valid_tau_in_every_deviation():
    """allantools ends every deviation in remove_small_ns, which raises UserWarning when no tau
    keeps two terms: HDEV and OHDEV of 3 phase points, GRADEV of 2 points or all NaN too."""
    for call in (lambda: at.hdev(np.array([1.0, 2.0, 4.0])), lambda: at.ohdev(np.array([1.0, 2.0, 4.0])),
                 lambda: at.hdev(np.array([1.0, 2.0]), data_type="freq"),
                 lambda: at.hdev(np.arange(4.0) ** 2, taus=[2]), lambda: at.gradev(np.array([1.0, 2.0])),
                 lambda: at.gradev(np.full(50, np.nan)), lambda: at.htotdev(np.array([])),
                 lambda: at.gcodev(np.array([1.0, 2.0]), np.array([1.0, 2.0]))):
        with pytest.raises(at.NoValidTau) as e:
            call()
        assert isinstance(e.value, UserWarning)


def _second_difference_adev(x, m, stride):
    """SP1065 eqn 7 (stride m) / eqn 11 (stride 1) on phase x, rate 1, written out."""
    n = len(range(2 * m, len(x), stride))
    v = np.array([x[i + 2 * m] - 2 * x[i + m] + x[i] for i in range(0, n * stride, stride)])
    return np.sqrt(np.sum(v * v) / (2.0 * n)) / m


def test_a_bad_phase_sample_blanks_only_the_taus_whose_terms_touch_it():
    """allantools' ADEV and HDEV take every m-th phase point (stride m) and PDEV never reads the
    last point: a NaN elsewhere leaves those taus' values; the overlapping statistics read every
    point, so all their taus are NaN. A single inf gives inf (its squared term), as numpy does."""
    x = np.cumsum(np.random.default_rng(3).normal(size=40))
    taus = [1, 2, 3, 4, 6, 8]
    bad = x.copy()
    bad[10] = np.nan  # 10 is a multiple of m = 1, 2 only (and 10 <= (n + 1) m for both)
    _, d, _, n = at.adev(bad, taus=taus)
    assert np.all(np.isnan(d[:2]))
    np.testing.assert_allclose(d[2:], [_second_difference_adev(x, m, m) for m in (3, 4, 6, 8)], rtol=1e-12)
    np.testing.assert_array_equal(n, at.adev(x, taus=taus)[3])
    _, d, _, _ = at.hdev(bad, taus=taus)
    assert np.all(np.isnan(d[:2])) and np.all(np.isfinite(d[2:]))
    assert np.all(np.isnan(at.oadev(bad, taus=taus)[1])) and np.all(np.isnan(at.ohdev(bad, taus=taus)[1]))
    last = x.copy()
    last[-1] = np.nan  # 39: a multiple of m = 1, 3 only; m = 2, 4, 6, 8 stop before it
    _, d, _, _ = at.adev(last, taus=taus)
    assert np.isnan(d[0]) and np.isnan(d[2]) and np.all(np.isfinite(d[[1, 3, 4, 5]]))
    np.testing.assert_allclose(d[1], _second_difference_adev(x, 2, 2), rtol=1e-12)
    _, d, _, _ = at.pdev(last, taus=taus)
    assert np.isnan(d[0]) and np.all(np.isfinite(d[1:]))  # m = 1 is the OADEV; m > 1 stop at N - 2
    np.testing.assert_allclose(d[1:], at.pdev(x, taus=taus)[1][1:], rtol=1e-12)  # the last point unread
    inf = x.copy()
    inf[5] = np.inf
    _, d, _, _ = at.oadev(inf, taus=[1, 2])
    assert list(d) == [np.inf, np.inf]
    _, d, _, _ = at.adev(inf, taus=[1, 2, 5])
    assert np.isinf(d[0]) and np.isfinite(d[1]) and np.isinf(d[2])


def test_gcodev_takes_input_as_the_deviations_do():
    """gcodev's data pass through allantools' input_to_phase: end NaN of frequency data trimmed,
    a NaN inside phase data gives NaN (every term of the overlapping estimator reads each point);
    float32 taus give float32 results, in gradev too."""
    rng = np.random.default_rng(6)
    a = rng.normal(size=300)
    b = 0.5 * a + rng.normal(size=300)
    pa, pb = (np.concatenate(([np.nan], v, [np.nan])) for v in (a, b))
    for u, v in zip(at.gcodev(pa, pb, data_type="freq", taus=[1, 2]), at.gcodev(a, b, data_type="freq", taus=[1, 2])):
        np.testing.assert_array_equal(u, v)
    _, g, _, _ = at.gcodev(a, a, data_type="freq", taus=[1, 2])
    np.testing.assert_allclose(g, at.oadev(a, data_type="freq", taus=[1, 2])[1], rtol=1e-12)  # codev(a, a) = adev
    inside = a.copy()
    inside[5] = np.nan
    t, g, _, n = at.gcodev(inside, b, taus=[1, 2])
    assert np.all(np.isnan(g)) and list(n) == [298, 296]
    t32 = np.array([2.0, 4.0], dtype=np.float32)
    assert all(v.dtype == np.float32 for v in at.gcodev(a, b, taus=t32))
    t, d, (lo, hi), n = at.gradev(a, taus=t32)
    assert t.dtype == d.dtype == lo.dtype == hi.dtype == n.dtype == np.float32


def test_rates_beyond_the_cores_interval_are_rescaled():
    """allantools has no bound on the rate: a 1.5 GHz phase record (a time-interval analyser)
    gives ADEV = SP1065 eqn 7 with tau0 = 1 / rate; the time statistics (TDEV, MTIE, TIERMS) are
    in phase units and do not change with the rate for phase data; frequency data integrate to
    phase in units of tau0, so their ADEV does not change and their TDEV scales with tau0."""
    x = np.cumsum(np.random.default_rng(4).normal(size=400)) * 1e-12
    for rate in (1.5e9, 1e-12):
        t, d, _, _ = at.adev(x, rate=rate, taus=np.array([1.0, 4.0]) / rate)
        np.testing.assert_allclose(t * rate, [1.0, 4.0])
        np.testing.assert_allclose(d, [_second_difference_adev(x, m, m) * rate for m in (1, 4)], rtol=1e-12)
        for f in (at.tdev, at.mtie, at.tierms):
            np.testing.assert_allclose(f(x, rate=rate, taus=[4 / rate])[1], f(x, taus=[4.0])[1], rtol=1e-12)
        y = np.diff(x)
        for f, power in ((at.oadev, 0), (at.totdev, 0), (at.tdev, -1), (at.gradev, 0)):
            np.testing.assert_allclose(f(y, rate=rate, data_type="freq", taus=[4 / rate])[1],
                                       f(y, data_type="freq", taus=[4.0])[1] * rate ** power, rtol=1e-12)
    for bad in (0.0, -1.0, float("nan"), "x"):
        with pytest.raises(at.RateError):
            at.gcodev(x, x, rate=bad)


def test_theo1_and_tierms_errors_as_allantools_computes_them():
    """allantools' theo1 returns devs / sqrt(N - m) (N phase points; its ns are the (N - m) m / 2
    inner terms) and tierms zeros (its own TODO); the others devs / sqrt(ns)."""
    x = np.cumsum(np.random.default_rng(5).normal(size=101))
    t, d, e, n = at.theo1(x, taus=[2, 4, 10])
    np.testing.assert_allclose(e, d / np.sqrt(101 - np.array([2, 4, 10])), rtol=1e-15)
    np.testing.assert_array_equal(n, (101 - t) * t / 2)
    t, d, e, n = at.tierms(x, taus=[1, 2])
    assert np.all(d > 0) and list(e) == [0, 0]


def test_mtie_and_tierms_of_frequency_data_remove_its_mean_as_frequency2phase_does():
    """allantools integrates frequency data with frequency2phase, which subtracts the mean first,
    so a frequency offset leaves its MTIE and TIE rms unchanged (gyroflip's own API keeps it:
    a bias is a time error)."""
    y = np.random.default_rng(11).normal(size=2000)
    for f in (at.mtie, at.tierms):
        _, d0, _, _ = f(y, data_type="freq", taus=[1, 10, 100])
        _, d5, _, _ = f(y + 5.0, data_type="freq", taus=[1, 10, 100])
        _, dp, _, _ = f(at.frequency2phase(y + 5.0, 1.0), data_type="phase", taus=[1, 10, 100])
        np.testing.assert_allclose(d5, d0, rtol=1e-9)
        np.testing.assert_allclose(d5, dp, rtol=1e-9)


def test_realtime_auto_afs_grows_the_factors_in_every_class():
    """allantools' realtime classes with auto_afs=True add the next factor of the grid
    round(10^k logspace(0, 1, pts_per_decade + 1)) once 2 af + 1 points exist: 200 points give
    1, 2, 3, 6, 10, 18, 32, 56 (100 needs 201). OHDEV's terms start at 3 af + 1 points, after
    the factor is there, so its streamed values equal the batch OHDEV."""
    x = np.cumsum(np.random.default_rng(8).normal(size=200))
    grid = [1, 2, 3, 6, 10, 18, 32, 56]
    for cls in (at.oadev_realtime, at.ohdev_realtime, at.tdev_realtime):
        s = cls(auto_afs=True, pts_per_decade=4)
        for v in x:
            s.add_phase(v)
        assert list(s.taus()) == grid and len(s.devs()) == len(grid), cls.__name__
    h = at.ohdev_realtime(auto_afs=True, tau0=0.5)
    for v in x:
        h.add_phase(v)
    np.testing.assert_allclose(h.devs(), at.ohdev(x, rate=2.0, taus=np.array(grid) / 2.0)[1], rtol=1e-10)
    assert at.tdev_realtime(afs=[1, 2]).afs == [1, 2]  # kept as passed


def test_confidence_interval_takes_arrays_and_gives_scipys_edge_values():
    """allantools' confidence_interval is NumPy arithmetic around scipy.stats.chi2.ppf: an array
    of devs gives arrays; ci = 1 gives chi2.ppf(0) = 0 and ppf(1) = inf, so (0, inf); edf <= 0
    gives ppf = NaN. edf_simple's flicker-PM form takes np.log of (N - 1)/(2m) < 1: NaN."""
    lo, hi = at.confidence_interval(np.array([1.0, 2.0]), 10.0, ci=0.9)
    np.testing.assert_allclose(lo, np.sqrt(10 / 18.307038) * np.array([1, 2]), rtol=1e-6)
    np.testing.assert_allclose(hi, np.sqrt(10 / 3.940299) * np.array([1, 2]), rtol=1e-6)
    assert at.confidence_interval(1.0, 10, 1.0) == (0.0, np.inf)
    for bad in (0.0, -3.0):
        assert all(np.isnan(v) for v in at.confidence_interval(1.0, bad))
    assert np.isnan(at.edf_simple(10, 10, 1)) and np.isnan(at.edf_totdev(10, 10, 1))


def test_write_results_writes_allantools_table(tmp_path):
    """allantools' Dataset.write_results: '#' lines (generator, input data type, input data rate,
    `key: value` per header_params), a line of column names, then AF, Tau, N, alpha ("NaN"),
    dev - err/2, dev, dev + err/2 with digits - 1 decimals."""
    ds = at.Dataset(data=NBS14_PHASE, rate=1.0, data_type="phase", taus=[1, 2])
    ds.compute("oadev")
    assert "stat_unc" not in ds.out
    path = tmp_path / "r.txt"
    ds.write_results(str(path), digits=5, header_params={"a": 1})
    lines = path.read_text().splitlines()
    assert lines[1:4] == ["# Input data type: phase", "# Input data rate: 1.0", "# a: 1"]
    assert lines[4].split() == ["AF", "Tau", "N", "alpha", "min_oadev", "oadev", "max_oadev"]
    rows = [line.split() for line in lines[5:]]
    assert [r[0] for r in rows] == ["1", "2"] and [r[2] for r in rows] == ["8", "6"]
    assert [r[3] for r in rows] == ["NaN", "NaN"] and rows[0][5] == "9.1229e+01"  # NBS14 91.22945
    t, d, e, n = (ds.out[k] for k in ("taus", "stat", "stat_err", "stat_n"))
    table = np.array([[float(v) for v in r[4:7]] for r in rows])
    np.testing.assert_allclose(table, np.column_stack((d - e / 2, d, d + e / 2)), rtol=1e-4)


def test_plot_takes_no_display_first_and_needs_matplotlib(monkeypatch):
    """allantools' Plot(no_display=False): the one positional argument is no_display
    (matplotlib.use("Agg")); without matplotlib, RuntimeError("Matplotlib is required ...")."""
    import types
    used = []
    mpl = types.ModuleType("matplotlib")
    mpl.use = used.append
    pyplot = types.ModuleType("matplotlib.pyplot")

    class Axes:
        def __getattr__(self, name):
            return lambda *a, **k: used.append(name)

    pyplot.subplots = lambda: (object(), Axes())
    mpl.pyplot = pyplot
    monkeypatch.setitem(sys.modules, "matplotlib", mpl)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", pyplot)
    p = at.Plot(True)
    assert used[0] == "Agg"
    ds = at.Dataset(data=NBS14_PHASE, taus=[1, 2])
    ds.compute("adev")
    p.plot(ds, grid=False)
    assert used[-1] == "grid"
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(RuntimeError, match="Matplotlib is required"):
        at.Plot()


def test_noise_prefactors_pdev_and_current_constants():
    """Noise.pdev_from_qd (allantools 2024.04+): PVAR = prefactor^2 tau^c (Vernotte et al. 2016
    Table I) matches the PDEV of the module's own Kasdin noise at tau = 16 for white PM, white
    FM, flicker FM and random-walk FM (flicker PM's PVAR has a log tau term the constant leaves
    out). Flicker FM MVAR = (27/20) ln 2 h_-1 (Benkler et al. 2015 Table 1) and flicker PM AVAR
    = (3 gamma - ln 2 + 3 ln(2 pi f_h tau)) h_1 / (4 pi^2) (Vernotte Table I), as allantools."""
    for b, c in ((0, -3), (-2, -1), (-3, 0), (-4, 1)):
        ratios = []
        for seed in (0, 1):
            np.random.seed(seed)
            n = at.Noise(2 ** 14, 1.0, b)
            n.generateNoise()
            _, d, _, _ = at.pdev(n.time_series, taus=[16.0])
            ratios.append(d[0] / (n.pdev_from_qd() * 16.0 ** (c / 2)))
        assert np.mean(ratios) == pytest.approx(1.0, abs=0.08), b
    ffm = at.Noise(8, 1.0, -3)
    assert ffm.mdev_from_qd() ** 2 == pytest.approx(27 / 20 * np.log(2) * ffm.frequency_psd_from_qd(), rel=1e-12)
    fpm = at.Noise(8, 1.0, -1)
    expect = (3 * 0.5772156649015329 - np.log(2) + 3 * np.log(2 * np.pi * 0.5 * 4.0)) / (4 * np.pi ** 2)
    assert fpm.adev_from_qd(1.0, 4.0) ** 2 == pytest.approx(expect * fpm.frequency_psd_from_qd(), rel=1e-12)


def test_calc_primitives_take_any_stride_and_keep_single_terms():
    """allantools' calc_hdev_phase(phase, rate, mj, stride) sums the third differences
    x[i + 3mj] - 3x[i + 2mj] + 3x[i + mj] - x[i] for i = 0, stride, 2 stride, ...: HDEV = sqrt(
    sum / (6 n)) / (mj tau0), (0, 0, 1) without a term; its calc_mtotdev_phase keeps n = 1."""
    x = np.cumsum(np.random.default_rng(1).normal(size=60))
    for mj, stride, rate in ((4, 2, 1.0), (4, 4, 2.0), (3, 1, 1.0)):
        v = np.array([x[i + 3 * mj] - 3 * x[i + 2 * mj] + 3 * x[i + mj] - x[i]
                      for i in range(0, 60 - 3 * mj, stride)])
        dev, err, n = at.calc_hdev_phase(x, rate, mj, stride)
        assert n == len(v) and isinstance(n, int)
        assert dev == pytest.approx(np.sqrt(np.sum(v * v) / (6 * n)) * rate / mj, rel=1e-12)
        assert err == pytest.approx(dev / np.sqrt(n), rel=1e-12)
    assert at.calc_hdev_phase(x, 1.0, 30, 1) == (0.0, 0.0, 1)
    dev, err, n = at.calc_mtotdev_phase(x, 1.0, 20)  # N - 3m + 1 = 1 term
    assert n == 1 and dev == err > 0
    # allantools.allantools' calc_adev_phase (stride mj: ADEV, 1: OADEV) and calc_pdev_phase.
    for mj, stride in ((4, 4), (3, 1), (5, 2)):
        dev, err, n = at.allantools.calc_adev_phase(x, 1.0, mj, stride)
        if stride in (1, mj):
            assert dev == pytest.approx(_second_difference_adev(x, mj, stride), rel=1e-12)
        assert n == len(range(2 * mj, 60, stride))
    for mj in (1, 4, 7):
        dev, err, n = at.allantools.calc_pdev_phase(x, 1.0, mj)
        t, d, e, ns = at.pdev(x, taus=[mj])
        assert dev == pytest.approx(d[0], rel=1e-12) and n == ns[0]
