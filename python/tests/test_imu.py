"""Issue 34 items 3 and 6 in Python: rate required wherever a default would assume 1 Hz, the IMU
reader, multi-axis and accelerometer noise(), plot(), write_kalibr() read with the rules of
Kalibr's reader, and `import allantools` code running unchanged through gyroflip.allantools."""
import importlib.util
import inspect
import os
import subprocess
import sys

import numpy as np
import pytest

import gyroflip
from conftest import EXE, VECTORS

RATE = 50.0
N = 60000  # 20 min


def white_plus_walk(n_density, k_density, seed, n=N, rate=RATE):
    """White noise of density n_density plus a random walk of density k_density (known truth)."""
    rng = np.random.default_rng(seed)
    dt = 1.0 / rate
    return (n_density / np.sqrt(dt) * rng.standard_normal(n)
            + np.cumsum(k_density * np.sqrt(dt) * rng.standard_normal(n)))


def kalibr_rules():
    path = os.path.join(VECTORS, "..", "support", "kalibr_imu_rules.py")
    spec = importlib.util.spec_from_file_location("kalibr_imu_rules", path)
    m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m)
    return m


# --- rate: no function of gyroflip's own assumes 1 Hz --------------------------------------

def test_every_function_with_a_sample_rate_requires_it():
    """gyroflip.noise(gx) returned ARW 10x off at 100 Hz: no gyroflip function taking a sample
    rate may default it (gyroflip.allantools keeps allantools' rate=1.0, for its code)."""
    y = white_plus_walk(0.01, 0.0, 1, n=4000)
    for name in ("adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "mtotdev", "ttotdev",
                 "htotdev", "theo1", "pdev", "mtie", "tierms"):
        with pytest.raises(TypeError):
            getattr(gyroflip, name)(y)
    for call in (lambda: gyroflip.deviation(y), lambda: gyroflip.deviation(y, "oadev"),
                 lambda: gyroflip.dynamic_deviation(y, window_s=10.0),
                 lambda: gyroflip.plan(0.1, static=y)):
        with pytest.raises(ValueError, match="rate must be given"):
            call()
    with pytest.raises(TypeError):
        gyroflip.noise(y)
    # No public function has rate=1.0 as its default (simulate's rate is a rate profile, "0").
    for name in gyroflip.__all__:
        f = getattr(gyroflip, name)
        if callable(f) and not inspect.isclass(f):
            p = inspect.signature(f).parameters.get("rate")
            assert p is None or p.default in (inspect.Parameter.empty, None, "0"), name
    # The shim keeps allantools' default.
    import gyroflip.allantools as at
    assert inspect.signature(at.oadev).parameters["rate"].default == 1.0


# --- multi-axis and accelerometer noise() --------------------------------------------------

def test_multi_axis_noise_and_the_accelerometer_from_the_column_unit():
    gx = white_plus_walk(0.004, 1e-4, 2)
    ax = white_plus_walk(0.002, 3e-4, 3)
    # A dict: one result per column; each column's unit from its name.
    d = gyroflip.noise({"gx_dps": gx, "ax_mps2": ax}, RATE)
    assert set(d) == {"gx_dps", "ax_mps2"}
    assert d["gx_dps"]["quantity"] == "gyro" and d["ax_mps2"]["quantity"] == "accel"
    assert abs(d["gx_dps"]["arw_dps_rthz"] / 0.004 - 1) < 0.05
    assert abs(d["ax_mps2"]["vrw_mps2_rthz"] / 0.002 - 1) < 0.05
    # The same as one axis at a time, and as a 2-D array (one axis per column).
    one = gyroflip.noise(ax, RATE, quantity="accel")
    assert one["vrw_mps2_rthz"] == d["ax_mps2"]["vrw_mps2_rthz"]
    two = gyroflip.noise(np.column_stack([gx, gx]), RATE)
    assert isinstance(two, list) and len(two) == 2
    assert two[0]["arw_dps_rthz"] == d["gx_dps"]["arw_dps_rthz"]
    with pytest.raises(ValueError, match="transpose"):
        gyroflip.noise(np.vstack([gx, gx]), RATE)
    # In mg: the same terms in m/s^2.
    mg = gyroflip.noise(ax * 1e3 / 9.80665, RATE, units="mg")
    assert mg["vrw_mps2_rthz"] == pytest.approx(one["vrw_mps2_rthz"], rel=1e-9)
    # Contradictions are refused, naming the column.
    with pytest.raises(ValueError, match="ax_mps2"):
        gyroflip.noise({"ax_mps2": ax}, RATE, units="deg/s")
    with pytest.raises(ValueError, match="quantity"):
        gyroflip.noise({"gx_dps": gx}, RATE, quantity="accel")


# --- read_imu ------------------------------------------------------------------------------

def test_read_imu_gives_columns_units_and_rate(tmp_path):
    gx, ax = white_plus_walk(0.004, 0.0, 4, n=2000), white_plus_walk(0.002, 0.0, 5, n=2000)
    p = tmp_path / "log.csv"
    t0 = 1_700_000_000_123_456_789
    with open(p, "w") as f:
        f.write("# a logger's comment\nstamp_ns;gx [rad/s];acc_x [m/s^2];label\n")
        for k in range(2000):
            f.write(f"{t0 + k * 20_000_000};{gx[k]!r};{ax[k]!r};ok\n")
    imu = gyroflip.read_imu(p)
    assert imu.rate_hz == pytest.approx(50.0, rel=1e-12)
    assert list(imu.columns) == ["gx [rad/s]", "acc_x [m/s^2]"]
    assert imu.units == {"gx [rad/s]": "rad/s", "acc_x [m/s^2]": "m/s^2"}
    assert imu.quantity == {"gx [rad/s]": "gyro", "acc_x [m/s^2]": "accel"}
    np.testing.assert_array_equal(imu.columns["acc_x [m/s^2]"], ax)
    r = imu.noise()
    assert r["gx [rad/s]"]["units"] == "rad/s"
    assert r["acc_x [m/s^2]"]["quantity"] == "accel"
    # A dropped sample is a gap: refused, naming the line.
    lines = open(p).read().splitlines()
    del lines[500]
    (tmp_path / "gap.csv").write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"gap.csv:501: column stamp_ns: the time stamp jumps"):
        gyroflip.read_imu(tmp_path / "gap.csv")
    (tmp_path / "bare.csv").write_text("gx\n1\n2\n3\n")
    with pytest.raises(ValueError, match="give rate=Hz"):
        gyroflip.read_imu(tmp_path / "bare.csv")


# --- plot() and write_kalibr() -------------------------------------------------------------

def test_plot_draws_the_cli_figure(tmp_path):
    gx = white_plus_walk(0.004, 1e-4, 6)
    out = gyroflip.plot({"gx_dps": gx, "gy_dps": gx[::-1].copy()}, RATE, tmp_path / "n.svg",
                        title="two axes")
    assert set(out) == {"gx_dps", "gy_dps"}
    svg = (tmp_path / "n.svg").read_text()
    assert "two axes" in svg and "gx_dps" in svg and "gy_dps" in svg
    assert (tmp_path / "n.gp").exists()
    # The CLI draws the same figure from the same numbers (its data files are identical).
    csv = tmp_path / "g.csv"
    with open(csv, "w") as f:
        f.write("time_s,gx_dps,gy_dps\n")
        for k in range(len(gx)):
            f.write(f"{k / RATE!r},{gx[k]!r},{gx[::-1][k]!r}\n")
    (tmp_path / "cli").mkdir()
    subprocess.run([EXE, "noise", str(csv), "--column", "gx_dps,gy_dps", "--plot",
                    str(tmp_path / "cli" / "n.svg"), "--title", "two axes"], check=True,
                   capture_output=True)
    for k in (1, 2, 3):
        a = (tmp_path / f"n_{k}.dat").read_text()
        b = (tmp_path / "cli" / f"n_{k}.dat").read_text()
        assert a == b, k
    # An accelerometer with a gyro: two figures.
    gyroflip.plot({"gx_dps": gx, "ax_mps2": white_plus_walk(0.002, 3e-4, 7)}, RATE,
                  tmp_path / "both.png")
    assert (tmp_path / "both.png").exists() and (tmp_path / "both_accel.png").exists()
    with pytest.raises(ValueError, match="png, .svg or .pdf"):
        gyroflip.plot(gx, RATE, tmp_path / "n.jpg")


def test_write_kalibr_loads_with_kalibrs_rules_and_holds_the_truth(tmp_path):
    pytest.importorskip("yaml")
    truth = {"gx_dps": (0.006, 3e-4), "gy_dps": (0.004, 1e-4), "ax_mps2": (0.002, 2e-4),
             "ay_mps2": (0.003, 4e-4)}
    cols = {c: white_plus_walk(n, k, 10 + i) for i, (c, (n, k)) in enumerate(truth.items())}
    gyro = gyroflip.noise({c: cols[c] for c in ("gx_dps", "gy_dps")}, RATE)
    accel = gyroflip.noise({c: cols[c] for c in ("ax_mps2", "ay_mps2")}, RATE)
    text = gyroflip.write_kalibr(tmp_path / "imu.yaml", gyro, accel, rostopic="/imu/data")
    k = kalibr_rules().check(tmp_path / "imu.yaml")
    assert text == (tmp_path / "imu.yaml").read_text()
    assert k["rostopic"] == "/imu/data" and k["update_rate"] == RATE
    # The largest axis; against the truth within 3 % (N) and 40 % (K: 20 min of record).
    rad = np.pi / 180
    assert k["gyroscope_noise_density"] == pytest.approx(0.006 * rad, rel=0.03)
    assert k["accelerometer_noise_density"] == pytest.approx(0.003, rel=0.03)
    assert k["gyroscope_random_walk"] == pytest.approx(3e-4 * rad, rel=0.4)
    assert k["accelerometer_random_walk"] == pytest.approx(4e-4, rel=0.4)
    assert k["gyroscope_noise_density"] == pytest.approx(
        max(r["arw_rad_s_rthz"] for r in gyro.values()), rel=1e-6)
    # The CLI writes the same file from the same record.
    csv = tmp_path / "imu.csv"
    with open(csv, "w") as f:
        f.write("time_s," + ",".join(cols) + "\n")
        for i in range(N):
            f.write(f"{i / RATE!r}," + ",".join(repr(cols[c][i]) for c in cols) + "\n")
    subprocess.run([EXE, "noise", str(csv), "--columns", "all-numeric", "--kalibr",
                    str(tmp_path / "cli.yaml"), "--rostopic", "/imu/data"], check=True,
                   capture_output=True)
    cli = kalibr_rules().check(tmp_path / "cli.yaml")
    for key in ("gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density",
                "accelerometer_random_walk"):
        assert cli[key] == pytest.approx(k[key], rel=2e-6), key
    # A gyro given as the accelerometer is refused; nothing written.
    with pytest.raises(ValueError, match="given as accel"):
        gyroflip.write_kalibr(tmp_path / "bad.yaml", gyro, gyro)
    assert not (tmp_path / "bad.yaml").exists()


# --- import allantools through the shim -----------------------------------------------------

ALLANTOOLS_CODE = r'''
import numpy as np
import allantools
import allantools.allantools
import allantools.ci as ci
import allantools.noise_kasdin
from allantools import noise
from allantools.realtime import oadev_realtime
from allantools.dataset import Dataset

y = noise.white(4096)
r = 10.0
(t2, ad, ade, adn) = allantools.oadev(y, rate=r, data_type="freq", taus="octave")
(t3, ad3, _, _) = allantools.allantools.oadev(y, rate=r, data_type="freq", taus="octave")
assert np.array_equal(ad, ad3) and len(t2) > 5
a = allantools.Dataset(data=y, rate=r, data_type="freq", taus="octave")
res = a.compute("mdev")
assert Dataset is allantools.Dataset
edf = ci.edf_greenhall(alpha=0, d=2, m=1, N=4096, overlapping=True, modified=False)
lo, hi = ci.confidence_interval(ad[0], edf)
assert lo < ad[0] < hi
n = allantools.noise_kasdin.Noise(1024, 1.0, 0)
n.generateNoise()
assert len(n.time_series) == 1024
rt = oadev_realtime(afs=[1, 2, 4], tau0=1.0)
for x in np.cumsum(y[:64]):
    rt.add_phase(x)
print("ok", allantools.__name__)
'''


def test_import_allantools_code_runs_unchanged_through_the_shim(tmp_path):
    """Code written as allantools' own examples and tests use it, after install(); in a fresh
    interpreter (sys.modules untouched here). Without install() `import allantools` fails (no
    allantools on this machine), which is what the shim replaces."""
    script = tmp_path / "user_code.py"
    script.write_text(ALLANTOOLS_CODE)
    env = dict(os.environ, PYTHONPATH=os.environ["GYROFLIP_PYTHON_DIR"])
    run = subprocess.run([sys.executable, "-c",
                          "import gyroflip.allantools; gyroflip.allantools.install(); "
                          f"exec(open({str(script)!r}).read())"],
                         capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "ok gyroflip.allantools"
    bare = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env)
    assert bare.returncode != 0 and "allantools" in bare.stderr


def test_install_refuses_to_shadow_another_allantools(monkeypatch):
    import types
    import gyroflip.allantools as shim
    other = types.ModuleType("allantools")
    monkeypatch.setitem(sys.modules, "allantools", other)
    with pytest.raises(RuntimeError, match="another allantools"):
        shim.install()
    assert sys.modules["allantools"] is other
    for name in shim.SUBMODULES:
        monkeypatch.delitem(sys.modules, "allantools." + name, raising=False)
    assert shim.install(replace=True) is shim
    assert sys.modules["allantools.ci"] is shim.ci
    assert sys.modules["allantools.allantools"] is shim.allantools
