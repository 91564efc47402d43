"""Bad input raises ValueError (data, arguments) or OSError (files) with the CLI's messages."""
import os
import subprocess

import numpy as np
import pytest

import gyroflip


def test_non_finite_sample_names_it():
    y = np.ones(100)
    y[42] = np.nan
    with pytest.raises(ValueError, match=r"sample 42 \(0-based\) is not finite"):
        gyroflip.deviation(y, rate=1.0)
    with pytest.raises(ValueError, match="sample 42"):
        gyroflip.oadev(y, data_type="freq", rate=1.0)


@pytest.mark.parametrize("kwargs, match", [
    ({"rate": 0.0}, "rate must be a positive"),
    ({"rate": float("inf")}, "rate must be a positive"),
    ({"kind": "xdev"}, "unknown statistic 'xdev'"),
    ({"input": "voltage"}, "input must be 'rate' or 'angle'"),
    ({"ci": 1.5}, r"confidence level must be a probability in \(0, 1\).*\(argument ci\)"),
    ({"taus": "weekly"}, "weekly"),
    ({"taus": [-1.0]}, "taus must be"),
])
def test_bad_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        gyroflip.deviation(np.ones(100), **{"rate": 1.0, **kwargs})


def test_two_dimensional_data_is_refused():
    with pytest.raises(ValueError, match="1-D"):
        gyroflip.deviation(np.ones((10, 10)), rate=1.0)


def test_too_short():
    with pytest.raises(ValueError):
        gyroflip.oadev([1.0], data_type="freq", rate=1.0)


def test_bad_data_type():
    with pytest.raises(ValueError, match="data_type must be 'phase' or 'freq'"):
        gyroflip.adev(np.ones(10), data_type="angle", rate=1.0)


def test_missing_file_is_oserror(tmp_path):
    with pytest.raises(OSError, match="nothing.csv"):
        gyroflip.read_recording(tmp_path / "nothing.csv")


def test_bad_recording_names_line_and_column(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_text("time_s,angle_deg,rate_dps\n0,0,1\n1,90,1\n")
    with pytest.raises(ValueError, match=r"bad.csv:3:\d+: angle 90 deg is not supported"):
        gyroflip.read_recording(p)


def test_bad_columns():
    t = np.arange(10.0)
    a = np.tile([0.0, 180.0], 5)
    with pytest.raises(ValueError, match=r"angle_deg\[3\]: angle 90 deg"):
        gyroflip.calibrate(t, np.where(np.arange(10) == 3, 90.0, a), np.ones(10))
    with pytest.raises(ValueError, match="rate_dps has 9 values but time_s has 10"):
        gyroflip.calibrate(t, a, np.ones(9))
    with pytest.raises(ValueError, match=r"time_s\[5\]: time goes backwards"):
        gyroflip.calibrate(np.where(np.arange(10) == 5, 0.0, t), a, np.ones(10))
    with pytest.raises(ValueError, match="latitude and axis together"):
        gyroflip.calibrate(t, a, np.ones(10), latitude=42.6)
    with pytest.raises(ValueError, match="never turns"):
        gyroflip.calibrate(t, np.zeros(10), np.ones(10))


def test_compensate_needs_one_dn():
    t = np.arange(10.0)
    a = np.tile([0.0, 180.0], 5)
    with pytest.raises(ValueError, match="either delta_n_dps or calibration"):
        gyroflip.compensate(t, a, np.ones(10))
    with pytest.raises(ValueError, match="not a gyroflip calibration"):
        gyroflip.compensate(t, a, np.ones(10), calibration={"x": 1})


def test_simulate_bad_arguments():
    with pytest.raises(OSError, match="no-such-sensor.*not a built-in sensor"):
        gyroflip.simulate("no-such-sensor")
    with pytest.raises(ValueError, match="duration"):
        gyroflip.simulate("adxrs150", duration_s=-1)


def _recording():
    rec = gyroflip.read_recording(os.path.join(os.environ["GYROFLIP_VECTORS_DIR"], "demo",
                                               "run_rate_table_20c.csv"))
    return [rec[k] for k in ("time_s", "angle_deg", "rate_dps", "temp_c", "n_avg")]


def _cli(*args):
    return subprocess.run([os.environ["GYROFLIP_EXE"], *map(str, args)], capture_output=True, text=True)


# Issue 21: gyroflip.compensate(..., delta_n_dps=1e300) returned NaN and inf where the CLI refuses
# --delta-n 1e300; a drift window of inf came back as inf; time stamps of 1e300 were taken where a
# CSV cell is refused beyond 1e100. The rules live in the library, and both front ends call them:
# the same values are refused by both with the same message.
@pytest.mark.parametrize("dn", [1e300, -1e101, float("inf"), float("nan")])
def test_compensate_applies_the_clis_dn_rule(dn):
    cols = _recording()
    with pytest.raises(ValueError, match=r"dN must be a finite number of deg/s within \+-1e\+100; "
                                         r".*\(argument delta_n_dps\)"):
        gyroflip.compensate(*cols, delta_n_dps=dn)
    cli = _cli("compensate", os.path.join(os.environ["GYROFLIP_VECTORS_DIR"], "demo",
                                          "run_rate_table_20c.csv"), "--delta-n", dn)
    assert cli.returncode == 2
    assert "dN must be a finite number of deg/s within +-1e+100" in cli.stderr, cli.stderr
    assert "(option --delta-n)" in cli.stderr


def test_every_number_python_returns_is_finite_within_the_bounds():
    cols = _recording()
    r = gyroflip.compensate(*cols, delta_n_dps=1e100)  # the bound itself: all finite
    for k in ("time_s", "rate_dps", "bias_dps", "delta_n_dps"):
        assert np.all(np.isfinite(r[k])), k
    assert all(np.isfinite(v) for v in r["summary"].values() if isinstance(v, float))
    for w in (float("inf"), 0.0, 2e9):
        with pytest.raises(ValueError, match=r"drift window must be in \(0, 1e\+09\] s.*"
                                             r"\(argument drift_window_s\)"):
            gyroflip.compensate(*cols, delta_n_dps=0.1, drift_window_s=w)
        cli = _cli("compensate", os.path.join(os.environ["GYROFLIP_VECTORS_DIR"], "demo",
                                              "run_rate_table_20c.csv"), "--delta-n", 0.1,
                   "--drift-window", w)
        assert cli.returncode == 2 and "(option --drift-window)" in cli.stderr, (w, cli.stderr)
    for t in (cols[0] * 1e298, np.where(np.arange(len(cols[0])) == 3, 1e101, cols[0])):
        with pytest.raises(ValueError, match=r"time_s\[\d+\]: not a finite number within \+-1e100"):
            gyroflip.calibrate(t, *cols[1:])
    y = np.random.default_rng(21).normal(size=20000)
    for lo, hi in ((float("nan"), 1.0), (-1.0, 1.0), (2.0, 1.0), (0.0, float("nan"))):
        with pytest.raises(ValueError, match=r"\(argument fit_taus\)"):
            gyroflip.noise(y, rate=100.0, fit_taus=(lo, hi))
    with pytest.raises(ValueError, match=r"\(argument ci\)"):
        gyroflip.noise(y, rate=100.0, ci=float("nan"))
    # Issue 34 item 6: no silent 1 Hz (the ARW of a 100 Hz record came out 10x off).
    with pytest.raises(TypeError, match="rate"):
        gyroflip.noise(y)


@pytest.mark.parametrize("kwargs, error, match", [
    ({"campaigns": 1.5}, TypeError, r"campaigns must be an int, not float"),
    ({"campaigns": 2.9}, TypeError, r"campaigns must be an int, not float"),
    ({"campaigns": "2"}, TypeError, r"campaigns must be an int, not str"),
    ({"campaigns": True}, TypeError, r"campaigns must be an int, not bool"),
    ({"campaigns": -1}, ValueError, r"campaigns must be an int in 1\.\.1000 \(got -1\)"),
    ({"campaigns": 1001}, ValueError, r"campaigns must be an int in 1\.\.1000"),
    ({"seed": 1.7}, TypeError, r"seed must be an int, not float"),
    ({"seed": "3"}, TypeError, r"seed must be an int, not str"),
    ({"seed": -1}, ValueError, r"seed must be an int in 0\.\.18446744073709551615 \(got -1\)"),
    ({"seed": 2**70}, ValueError, r"seed must be an int in 0\.\."),
    ({"quick": "yes"}, TypeError, r"quick must be a bool"),
    ({"sensors": ["hz1-90-100a"]}, TypeError, r"sensors must be a dict \{name: TOML file\}"),
    ({"sensors": {1: "x.toml"}}, TypeError, r"sensors: a name must be a str, not int"),
    ({"sensors": {"hz1-90-100a": 3}}, TypeError, r"sensors\['hz1-90-100a'\] must be a path"),
    ({"sensors": {"adxrs300": "x.toml"}}, ValueError,
     r"'adxrs300' is not one of the paper's sensors \(adxrs150, hz1-90-100a\) \(argument sensors\)"),
    ({"sensors": {"adxrs150": "/nonexistent/x.toml"}}, OSError, r"/nonexistent/x\.toml"),
])
def test_reproduce_checks_its_arguments_before_the_library(kwargs, error, match):
    """Review of issue 22, R10: campaigns=1.5 ran 1 campaign, '2' ran 2, seed=-1 gave pybind's
    "incompatible function arguments" with the private signature. Each now names the argument."""
    with pytest.raises(error, match=match) as e:
        gyroflip.reproduce(**{"quick": True, **kwargs})
    assert "incompatible function arguments" not in str(e.value)


def test_report_and_calibrate_runs_check_their_arguments(tmp_path):
    """Review R10: expected_rate='0.5' was accepted, a single str was wrapped and recorded as a
    list, a calibrate_runs() dict gave 'expected str, bytes or os.PathLike object, not dict',
    degree=-1 pybind's error. Nothing is written when an argument is wrong."""
    out = tmp_path / "rep"
    cases = [
        (dict(files="a.csv", output=out), TypeError, r"files must be a list or tuple of paths, not a single path \(write \['a.csv'\]\)"),
        (dict(files=[1], output=out), TypeError, r"files\[0\] must be a path"),
        (dict(files=["a.csv"], output=out, expected_rate="0.5", calibration="c.json"), TypeError,
         r"expected_rate must be a real number, not str"),
        (dict(files=["a.csv"], output=out, latitude="42"), TypeError, r"latitude must be a real number, not str"),
        (dict(files=["a.csv"], output=out, calibration={"delta_n_dps": 0.003}), TypeError,
         r"calibration must be the path of a calibration file"),
    ]
    for kwargs, error, match in cases:
        with pytest.raises(error, match=match):
            gyroflip.report(**kwargs)
    assert not out.exists()
    for kwargs, error, match in [
        (dict(files="a.csv"), TypeError, r"files must be a list or tuple of paths"),
        (dict(files=["a.csv"], degree=-1), ValueError, r"degree must be an int in 0\.\.6 \(got -1\)"),
        (dict(files=["a.csv"], degree=1.0), TypeError, r"degree must be an int, not float"),
        (dict(files=["a.csv"], latitude="x"), TypeError, r"latitude must be a real number"),
    ]:
        with pytest.raises(error, match=match) as e:
            gyroflip.calibrate_runs(**kwargs)
        assert "incompatible function arguments" not in str(e.value)


def test_kinds_without_intervals_read_no_noise_type():
    # Review E-L2: PDEV, MTIE and TIE rms have no EDF; like the CLI's nulls, no level, no type,
    # and the guard refused (the CLI refuses --ci-guard there).
    x = np.random.default_rng(3).normal(size=1001)
    for kind in ("pdev", "mtie", "tierms"):
        d = gyroflip.deviation(x, kind=kind, input="angle", rate=1.0)
        assert d.ci is None and np.all(np.isnan(d.alpha)) and np.all(np.isnan(d.edf))
        with pytest.raises(ValueError, match="guard applies to the kinds with intervals"):
            gyroflip.deviation(x, kind=kind, input="angle", guard=True, rate=1.0)
    assert np.all(np.isnan(gyroflip.deviation(x, input="angle", ci=None, rate=1.0).alpha))
    with pytest.raises(ValueError, match="guard guards intervals"):  # review F-L2, as the CLI
        gyroflip.deviation(x, input="angle", ci=None, guard=True, rate=1.0)
    assert np.all(gyroflip.deviation(x, input="angle", rate=1.0).alpha == 2)  # white PM read


def test_theo1_odd_factors_are_named():
    # Review E-L1: an odd factor alone read "series too short"; in a list it vanished silently.
    x = np.random.default_rng(4).normal(size=1001)
    with pytest.raises(ValueError, match=r"theo1 needs even averaging factors .*\[9\] odd"):
        gyroflip.deviation(x, kind="theo1", input="angle", taus=[9], rate=1.0)
    with pytest.warns(UserWarning, match=r"\[9\] dropped"):
        d = gyroflip.deviation(x, kind="theo1", input="angle", taus=[8, 9, 16], rate=1.0)
    assert list(d.m) == [8, 16]
    with pytest.raises(ValueError, match="taus is empty"):
        gyroflip.deviation(x, input="angle", taus=[], rate=1.0)


# Review of issue 31: compensate applied a calibration its own file marks as not stationary
# without a word. It warns (in "warnings"), and strict=True refuses it, as `compensate --strict`.
def test_compensate_warns_about_and_strict_refuses_a_calibration_of_a_turning_run():
    def run(rate, seed):
        rec = gyroflip.simulate("hz1-90-100a", duration_s=600, seed=seed, temp=20, rate=rate)
        return (rec["time_s"], rec["angle_deg"], rec["rate_dps"], rec["temp_c"], rec["n_avg"])
    still, turning = run("0", 32), run("0.5", 31)
    bad = gyroflip.calibrate(*turning, sensor="hz1-90-100a")
    assert not bad["files"][0]["stationarity"]["stationary"]
    r = gyroflip.compensate(*still, calibration=bad)
    assert any("not a stationary run" in w and "g-term" in w for w in r["warnings"]), r["warnings"]
    with pytest.raises(ValueError, match="not a stationary run"):
        gyroflip.compensate(*still, calibration=bad, strict=True)
    good = gyroflip.calibrate(*still, sensor="hz1-90-100a")
    assert gyroflip.compensate(*still, calibration=good, strict=True)["warnings"] == []


def test_a_table_line_gives_positions_by_index(tmp_path):
    # Issue 33: a recording's table (# positions_deg) is read, and each row carries its index
    # (270 deg is position 3, not "-1"); an angle not in it is refused at its line and column.
    p = tmp_path / "four.csv"
    p.write_text("# positions_deg: 0,90,180,270\ntime_s,angle_deg,rate_dps\n"
                 "0,0,1\n1,90,1\n2,180,1\n3,270,1\n4,,1\n")
    rec = gyroflip.read_recording(p)
    assert list(rec["position"]) == [0, 1, 2, 3, -1]
    assert list(rec["positions_deg"]) == [0, 90, 180, 270]
    assert list(rec["angle_deg"][:4]) == [0, 90, 180, 270]
    bad = tmp_path / "bad.csv"
    bad.write_text("# positions_deg: 0,90\ntime_s,angle_deg,rate_dps\n0,0,1\n1,180,1\n")
    with pytest.raises(ValueError, match=r"bad.csv:4:3: angle 180 deg is not supported: only 0 "
                                         r"and 90"):
        gyroflip.read_recording(bad)


# Review of issue 31 (H1): without a specification the g-term is not checked, and a run on a
# turning table returned stationary True with no warning, and strict=True accepted it.
def test_calibrate_without_a_sensor_warns_that_the_g_term_was_not_checked():
    rec = gyroflip.simulate("hz1-90-100a", duration_s=600, seed=31, temp=20, rate="0.5")
    turning = (rec["time_s"], rec["angle_deg"], rec["rate_dps"], rec["temp_c"], rec["n_avg"])
    r = gyroflip.calibrate(*turning)
    assert any("<arrays>: its g-term was not checked" in w and "sensor=" in w
               for w in r["warnings"]), r["warnings"]
    with pytest.raises(ValueError, match="g-term was not checked"):
        gyroflip.calibrate(*turning, strict=True)
    with pytest.raises(ValueError, match="its g-term is"):
        gyroflip.calibrate(*turning, sensor="hz1-90-100a", strict=True)


# Review of issue 31 (second review, item 3): report said nothing of its own run's unchecked
# g-term. It says it as calibrate does, naming the run, in Python's words (no CLI flag).
@pytest.mark.skipif(__import__("shutil").which("gnuplot") is None, reason="gnuplot not installed")
def test_report_warns_that_its_runs_g_term_was_not_checked(tmp_path):
    rec = gyroflip.simulate("hz1-90-100a", duration_s=600, seed=31, temp=20, rate="0.5")
    path = tmp_path / "turning.csv"  # no "# sensor_name:": no specification to check against
    with open(path, "w") as f:
        f.write("time_s,angle_deg,rate_dps,temp_c,n_avg\n")
        for t, a, r, c, n in zip(rec["time_s"], rec["angle_deg"], rec["rate_dps"], rec["temp_c"],
                                 rec["n_avg"]):
            f.write(f"{t!r},{'' if np.isnan(a) else repr(a)},{r!r},{c!r},{int(n)}\n")
    s = gyroflip.report([str(path)], tmp_path / "rep")
    hits = [w for w in s["warnings"] if f"{path}: its g-term was not checked" in w]
    assert hits and "sensor=" in hits[0] and "--sensor" not in hits[0], s["warnings"]
    page = (tmp_path / "rep" / "index.html").read_text()
    assert "was not checked (no sensor specification)" in page
