"""The module and the command line are one core: for the same input, the Python result equals
the CLI's JSON (adev, noise, calibrate, compensate) or file (simulate), number for number."""
import json
import re
import os
import shutil
import subprocess

import numpy as np
import pytest

import gyroflip


def run(exe, *args):
    p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True, check=True)
    return p.stdout


@pytest.fixture
def series_csv(tmp_path):
    y = np.random.default_rng(11).normal(size=20000) * 0.05 + 0.01 * np.sin(np.arange(20000) / 3e3)
    path = tmp_path / "y.csv"
    path.write_text("rate_dps\n" + "".join(f"{v!r}\n" for v in y))
    return path, y


@pytest.mark.parametrize("kind", ["oadev", "mdev", "totdev", "hdev"])
def test_deviation_equals_adev_json(exe, series_csv, kind):
    path, y = series_csv
    cli = json.loads(run(exe, "adev", path, "--rate", 100, "--kind", kind, "--json"))
    d = gyroflip.deviation(y, kind, rate=100.0, input="rate", taus="octave", ci=0.683)
    assert [p["m"] for p in cli["points"]] == list(d.m)
    for key, arr in [("dev", d.dev), ("ci_lo", d.ci_lo), ("ci_hi", d.ci_hi), ("edf", d.edf)]:
        np.testing.assert_array_equal([p[key] for p in cli["points"]], arr, err_msg=key)
    assert [p["alpha"] for p in cli["points"]] == list(d.alpha)


def test_ci_guard_equals_guard_true(exe, series_csv):
    """`adev --ci-guard` and deviation(guard=True) are one rule (issue 23): never a larger EDF
    than the default, the same noise types."""
    path, y = series_csv
    cli = json.loads(run(exe, "adev", path, "--rate", 100, "--ci-guard", "--json"))
    plain = json.loads(run(exe, "adev", path, "--rate", 100, "--json"))
    d = gyroflip.deviation(y, "oadev", rate=100.0, taus="octave", ci=0.683, guard=True)
    for key, arr in [("dev", d.dev), ("ci_lo", d.ci_lo), ("ci_hi", d.ci_hi), ("edf", d.edf)]:
        np.testing.assert_array_equal([p[key] for p in cli["points"]], arr, err_msg=key)
    assert [p["alpha"] for p in cli["points"]] == [p["alpha"] for p in plain["points"]]
    assert all(g["edf"] <= p["edf"] for g, p in zip(cli["points"], plain["points"]))


def test_noise_equals_noise_json(exe, series_csv):
    path, y = series_csv
    cli = json.loads(run(exe, "noise", path, "--rate", 100, "--json"))
    py = gyroflip.noise(y, rate=100.0, name=str(path), column="rate_dps")
    assert py == cli


def test_noise_in_rad_units_equals_cli(exe, series_csv, tmp_path):
    path, y = series_csv
    cli = json.loads(run(exe, "noise", path, "--rate", 100, "--units", "rad/s", "--json"))
    py = gyroflip.noise(y, rate=100.0, units="rad/s", name=str(path), column="rate_dps")
    assert py == cli


def test_calibrate_and_compensate_equal_the_cli(exe, vectors, tmp_path):
    cal_csv = os.path.join(vectors, "demo/cal_stationary_20c.csv")
    run_csv = os.path.join(vectors, "demo/run_rate_table_20c.csv")
    cli = json.loads(run(exe, "calibrate", cal_csv, "--latitude", 42.6, "--axis", "north", "--json"))
    rec = gyroflip.read_recording(cal_csv)
    assert rec["metadata"]  # the recording's `# key: value` lines
    cal = gyroflip.calibrate(rec["time_s"], rec["angle_deg"], rec["rate_dps"], rec["temp_c"],
                             rec["n_avg"], latitude=42.6, axis="north")
    for key in ["delta_n_dps", "std_dps", "stderr_dps", "stderr_correlated_dps", "cycles",
                "earth_rate_dps", "g_term_dps", "temp_c", "bias_mean_dps", "pairing"]:
        assert cal[key] == cli[key], key
    assert len(cal["cycle_values"]["rate_dps"]) == cli["cycles"]
    assert np.mean(cal["cycle_values"]["rate_dps"]) == pytest.approx(cal["delta_n_dps"], rel=1e-12)

    cal_path = tmp_path / "cal.json"
    run(exe, "calibrate", cal_csv, "--latitude", 42.6, "--axis", "north", "-o", cal_path)
    cli_comp = json.loads(run(exe, "compensate", run_csv, "--calibration", cal_path, "--json"))
    r = gyroflip.read_recording(run_csv)
    for calibration in (cal, cal_path, str(cal_path)):
        comp = gyroflip.compensate(r["time_s"], r["angle_deg"], r["rate_dps"], r["temp_c"],
                                   r["n_avg"], calibration=calibration)
        for key in ["cycles", "mean_dps", "std_dps", "stderr_dps", "stderr_correlated_dps",
                    "drift_dps", "duration_s", "pairing"]:
            assert comp["summary"][key] == cli_comp[key], key
        # The ΔN's errors (issue 31): the same numbers, or null with the same reason.
        if not isinstance(calibration, dict):
            for key in ["error_dps", "new_power_up_dps", "error_note"]:
                assert comp["summary"]["delta_n"][key] == cli_comp["delta_n"][key], key
    comp_csv = tmp_path / "comp.csv"
    run(exe, "compensate", run_csv, "--calibration", cal_path, "-o", comp_csv)
    with open(comp_csv) as f:
        assert f.readline().strip() == "time_s,rate_dps,bias_dps,temp_c,delta_n_dps"
    rows = np.loadtxt(comp_csv, delimiter=",", skiprows=1, comments="#")
    np.testing.assert_array_equal(rows[:, 1], comp["rate_dps"])
    np.testing.assert_array_equal(rows[:, 0], comp["time_s"])


def test_calibrate_runs_equals_the_cli(exe, tmp_path):
    """calibrate_runs and `gyroflip calibrate FILE... --json` are one library call (issue 22): the
    same object, every key, with the dN(T) line of runs at two temperatures."""
    files = []
    for seed, temp in ((1, 20), (2, 4), (3, 12)):
        f = tmp_path / f"c{temp}.csv"
        run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 300, "--seed", seed, "--temp", temp,
            "-o", f)
        files.append(f)
    cli = json.loads(run(exe, "calibrate", *files, "--latitude", 42.6, "--axis", "north", "--json"))
    py = gyroflip.calibrate_runs(files, latitude=42.6, axis="north")
    assert py.pop("warnings") == []
    assert py == cli
    assert cli["schema"] == "gyroflip.calibration/5" and cli["version"] == gyroflip.__version__
    assert cli["model"]["degree"] == 1
    one = gyroflip.calibrate_runs(files[:2], degree=1, pairing="simple")
    assert one["pairing"] == "simple" and one["model"]["degree"] == 1
    with pytest.raises(ValueError, match="a dN\\(T\\) model needs calibrations from several files"):
        gyroflip.calibrate_runs(files[:1], degree=1)


@pytest.mark.skipif(shutil.which("gnuplot") is None, reason="gnuplot not installed")
def test_report_equals_the_cli(exe, tmp_path):
    """gyroflip.report and `gyroflip report` are one library call (issue 22): the same
    summary.json but for the command that made it, and the same folder."""
    files = []
    for seed, temp in ((1, 20), (2, 4)):
        f = tmp_path / f"r{temp}.csv"
        run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 300, "--seed", seed, "--temp", temp,
            "-o", f)
        files.append(str(f))
    # sensor= is --sensor (fourth review of issue 31, F5: Python's report had no way to name it).
    run(exe, "report", *files, "--latitude", 42.6, "--axis", "north", "--sensor", "hz1-90-100a",
        "-o", tmp_path / "cli")
    cli = json.load(open(tmp_path / "cli" / "summary.json"))
    py = gyroflip.report(files, tmp_path / "py", latitude=42.6, axis="north", sensor="hz1-90-100a")
    # Two runs for a dN(T) line: no degrees of freedom left, which both say.
    assert len(py["warnings"]) == 1 and "0 degrees of freedom" in py["warnings"][0]
    assert py.pop("command").startswith("python3: gyroflip.report([")
    assert cli.pop("command").split()[1:3] == ["report", files[0]]
    py.pop("made_utc"), cli.pop("made_utc")
    # The next step is said in each front end's words (issue 31): the CLI's commands, Python's
    # calls; the rest of the conclusion is the same.
    assert "Next: gyroflip calibrate " in cli["conclusion"]
    assert "Next: cal = gyroflip.calibrate_runs([" in py["conclusion"]
    for d in (py, cli):
        d["conclusion"] = re.sub(r" Next: .*?(calibration=cal\)|--calibration cal\.json)\.", "",
                                 d["conclusion"])
    assert py == cli
    assert sorted(os.listdir(tmp_path / "py")) == sorted(os.listdir(tmp_path / "cli"))


def test_reproduce_equals_the_cli(exe):
    """gyroflip.reproduce and `gyroflip reproduce` are one library call (issue 22): the same
    text, the same summary."""
    cli = run(exe, "reproduce", "--quick", "--seed", 3)
    py = gyroflip.reproduce(quick=True, seed=3)
    # The same but the provenance line (its time and the command as made).
    def body(text):
        return [l for l in text.splitlines() if not l.startswith("made ")]
    made = [l for l in py["text"].splitlines() if l.startswith("made ")]
    assert len(made) == 1 and made[0].endswith(": python3: gyroflip.reproduce(quick=True, seed=3)")
    assert body(py.pop("text")) == body(cli)
    assert py["schema"].startswith("gyroflip.reproduce/") and py["campaigns"] == 1 and py["seed"] == 3
    assert py["command"] == "python3: gyroflip.reproduce(quick=True, seed=3)"


def test_reproduce_refuses_a_campaign_count_outside_its_range():
    """campaigns=0 was taken as the default (review of issue 22): 1 to 1000, else ValueError."""
    for k in (0, 1001):
        with pytest.raises(ValueError, match="campaigns"):
            gyroflip.reproduce(quick=True, campaigns=k)


def test_reproduce_puts_a_given_sensor_model_to_the_tests_as_the_cli(exe, tmp_path):
    """sensors={NAME: FILE.toml} is `--sensor NAME=FILE.toml` (issue 31): the same tests, the same
    text; an HZ1 with 3 times its ARW fails its noise tests (it read "reproduced" before)."""
    toml = tmp_path / "hz1_3x.toml"
    toml.write_text('name = "hz1-3x-arw"\nbase = "hz1-90-100a"\narw_dps_rthz = 0.0138\n')
    cli = run(exe, "reproduce", "--quick", "--sensor", f"hz1-90-100a={toml}")
    py = gyroflip.reproduce(quick=True, sensors={"hz1-90-100a": toml})
    assert py["verdict"] == "NOT reproduced" and not py["reproduced"]
    assert [p["id"] for p in py["predictions"] if p["outcome"] == "FAIL"] == ["fig8_std", "fig10_std"]
    model = py["given_sensor_models"][0]
    assert model["sensor"] == "hz1-90-100a" and model["file"] == str(toml) and len(model["sha256"]) == 64
    assert py["command"] == f"python3: gyroflip.reproduce(quick=True, sensors={{'hz1-90-100a': '{toml}'}})"
    def body(text):
        return [l for l in text.splitlines() if not l.startswith("made ")]
    assert body(py["text"]) == body(cli)


def test_simulate_equals_the_cli_file(exe, tmp_path):
    out = tmp_path / "sim.csv"
    run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 120, "--seed", 5, "--temp", 4,
        "-o", out)
    rows = gyroflip.read_recording(out)
    assert rows["metadata"]["seed"] == "5"
    s = gyroflip.simulate("hz1-90-100a", duration_s=120, seed=5, temp=4)
    for key in ["time_s", "angle_deg", "rate_dps", "temp_c", "n_avg"]:
        np.testing.assert_array_equal(rows[key], s[key], err_msg=key)
    # The truth: dN is the Earth term plus the g-term at 0 deg.
    assert s["delta_n_truth_dps"] == pytest.approx(
        s["earth_dps"][0] * (1 if s["angle_deg"][0] == 0 else -1)
        + s["g_term_dps"][0] * (1 if s["angle_deg"][0] == 0 else -1), rel=1e-2)


def test_readme_python_example_runs(tmp_path):
    """The README's Python block runs as written (with a gyro.npy beside it)."""
    readme = os.path.join(os.path.dirname(__file__), "..", "..", "README.md")
    text = open(readme).read()
    block = text.split("```python\n", 1)[1].split("```", 1)[0]
    assert len(block.strip().splitlines()) == 5
    np.save(tmp_path / "gyro.npy", np.random.default_rng(1).normal(size=1_000_000))
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        scope = {}
        exec(compile(block, "README.md", "exec"), scope)
    finally:
        os.chdir(cwd)
    assert abs(scope["cal"]["delta_n_dps"] - scope["rec"]["delta_n_truth_dps"]) < 0.01
    assert scope["taus"][0] == 0.01


@pytest.mark.parametrize("kind", ["mtotdev", "ttotdev", "htotdev", "theo1", "pdev", "mtie", "tierms"])
def test_extended_kinds_equal_adev_json(exe, series_csv, kind):
    """Issue 23: the new kinds through `adev --kind` and deviation() are one computation; the kinds
    without an EDF print null bounds (as --ci none)."""
    path, y = series_csv
    cli = json.loads(run(exe, "adev", path, "--rate", 100, "--kind", kind, "--json"))
    d = gyroflip.deviation(y, kind, rate=100.0, input="rate", taus="octave", ci=0.683)
    assert [p["m"] for p in cli["points"]] == list(d.m)
    np.testing.assert_array_equal([p["dev"] for p in cli["points"]], d.dev)
    np.testing.assert_array_equal([p["tau_s"] for p in cli["points"]], d.tau_s)
    if kind in ("mtotdev", "ttotdev", "htotdev", "theo1"):
        np.testing.assert_array_equal([p["ci_lo"] for p in cli["points"]], d.ci_lo)
    else:
        assert cli["ci"] is None and all(p["ci_lo"] is None for p in cli["points"])
        assert np.all(np.isnan(d.ci_lo))


def test_bias_correction_is_for_the_total_kinds_only(exe, series_csv):
    path, y = series_csv
    plain = json.loads(run(exe, "adev", path, "--rate", 100, "--kind", "htotdev", "--json"))
    corr = json.loads(run(exe, "adev", path, "--rate", 100, "--kind", "htotdev", "--json",
                          "--bias-correction"))
    d = gyroflip.deviation(y, "htotdev", rate=100.0, bias_correction=True)
    np.testing.assert_array_equal([p["dev"] for p in corr["points"]], d.dev)
    assert all(c["dev"] >= p["dev"] for c, p in zip(corr["points"], plain["points"]))
    bad = subprocess.run([exe, "adev", str(path), "--rate", "100", "--bias-correction"],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and "--bias-correction" in bad.stderr


def test_dynamic_deviation_equals_adev_dynamic_json(exe, series_csv):
    """DAVAR: `adev --dynamic W:S` and dynamic_deviation() are one computation, each window's
    curve the deviation of that window."""
    path, y = series_csv
    cli = json.loads(run(exe, "adev", path, "--rate", 100, "--dynamic", "40:20", "--json"))
    py = gyroflip.dynamic_deviation(y, "oadev", rate=100.0, window_s=40, step_s=20)
    assert len(cli["windows"]) == len(py) == (20000 - 4000) // 2000 + 1
    for c, p in zip(cli["windows"], py):
        assert c["start_s"] == p["start_s"]
        np.testing.assert_array_equal([q["dev"] for q in c["points"]], p["dev"])
        np.testing.assert_array_equal([q["ci_lo"] for q in c["points"]], p["ci_lo"])
        np.testing.assert_array_equal([q["alpha"] for q in c["points"]], p["alpha"])
    w = py[3]
    d = gyroflip.deviation(y[6000:10000], "oadev", rate=100.0)
    np.testing.assert_array_equal(w["dev"], d.dev)
    # Each window's bounds are those of deviation() on the window alone (its own noise type, the
    # EDF of its length); ci=None leaves them NaN.
    np.testing.assert_allclose(w["ci_lo"], d.ci_lo, rtol=1e-12)
    np.testing.assert_allclose(w["ci_hi"], d.ci_hi, rtol=1e-12)
    np.testing.assert_array_equal(w["alpha"], d.alpha)
    bare = gyroflip.dynamic_deviation(y, "oadev", rate=100.0, window_s=40, step_s=20, ci=None)
    assert np.all(np.isnan(bare[0]["ci_lo"]))
    with pytest.raises(ValueError):
        gyroflip.dynamic_deviation(y, window_s=1e6, rate=100.0)
    # Review E-L4: below one sample interval refused (was silently one sample), as the CLI.
    with pytest.raises(ValueError, match="shorter than one sample interval"):
        gyroflip.dynamic_deviation(y, window_s=40, step_s=0.004, rate=100.0)
    # Review F-M1: halves round up in both (Python's round() took 12.5 samples to 12, the CLI 13).
    cli = json.loads(run(exe, "adev", path, "--rate", 100, "--dynamic", "0.5", "--json", "--ci", "none"))
    py = gyroflip.dynamic_deviation(y, "oadev", rate=100.0, window_s=0.5, ci=None)
    assert cli["step_s"] == pytest.approx(0.13) and len(cli["windows"]) == len(py)
    assert [w["start_s"] for w in cli["windows"]] == pytest.approx([w["start_s"] for w in py])
    assert np.all(np.isnan(gyroflip.dynamic_deviation(y, "mtie", rate=100.0, window_s=40)[0]["alpha"]))


def test_codev_and_three_cornered_hat_in_the_cli(exe, tmp_path):
    """adev --codev (two columns) and --three-cornered-hat (three) against the drop-in's gcodev
    and three_cornered_hat_phase on the same samples: clocks of white FM 1, 2, 3."""
    import gyroflip.allantools as at
    rng = np.random.default_rng(3)
    a, b, c = rng.normal(size=(3, 20000)) * np.array([[1.0], [2.0], [3.0]])
    path = tmp_path / "clocks.csv"
    np.savetxt(path, np.c_[a - b, b - c, c - a, c - b], delimiter=",", header="ab,bc,ca,cb",
               comments="")
    hat = json.loads(run(exe, "adev", path, "--rate", 1, "--column", "ab,bc,ca",
                         "--three-cornered-hat", "--taus", "1,10", "--json"))
    assert [cv["clock"] for cv in hat["curves"]] == ["A", "B", "C"]
    for cv, sigma in zip(hat["curves"], (1.0, 2.0, 3.0)):
        assert cv["points"][0]["dev"] == pytest.approx(sigma, rel=0.05)
    _, da, _, _ = at.three_cornered_hat_phase(at.frequency2phase(a - b, 1), at.frequency2phase(b - c, 1),
                                              at.frequency2phase(c - a, 1), 1.0, [1.0, 10.0], at.oadev)
    np.testing.assert_allclose([p["dev"] for p in hat["curves"][0]["points"]], da, rtol=1e-9)
    co = json.loads(run(exe, "adev", path, "--rate", 1, "--column", "ab,cb", "--codev",
                        "--taus", "1,10", "--json"))
    _, g, _, _ = at.gcodev(a - b, c - b, data_type="freq", taus=[1.0, 10.0])
    np.testing.assert_allclose([abs(p["dev"]) for p in co["curves"][0]["points"]], g, rtol=1e-9)
    bad = subprocess.run([exe, "adev", str(path), "--rate", "1", "--column", "ab", "--codev"],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and "two columns" in bad.stderr


def test_plan_agrees_with_the_cli(exe):
    """gyroflip.plan gives what `gyroflip plan --json` prints, for a preset."""
    cli = json.loads(run(exe, "plan", "--sensor", "hz1-90-100a", "--dead-time", 0.4,
                         "--duration", 7200, "--json"))
    py = gyroflip.plan(0.4, sensor="hz1-90-100a", duration=7200)
    for key in ("dwell_s", "period_s", "predicted_sigma_dps", "sigma_without_dead_time_dps"):
        assert py[key] == cli[key], key
    assert py["schema"] == "gyroflip.plan/1"


def test_plan_of_a_static_record_finds_the_white_noise_limit():
    """White noise only: the best dwell is the longest the run allows relative to the dead time,
    and the error approaches N sqrt((tau + d) / (tau T)) (docs/PLANNER.md)."""
    rng = np.random.default_rng(7)
    n_true, rate = 0.01, 100.0
    y = rng.standard_normal(200_000) * n_true * np.sqrt(rate)
    p = gyroflip.plan(0.4, static=y, rate=rate, duration=3600.0)
    tau, d, T = p["dwell_s"], 0.4, 3600.0
    assert p["predicted_sigma_dps"] > 0
    # N recovered within a few per cent; the error follows the white-noise form at the plan
    assert abs(p["noise"]["arw_dps_rthz"] / n_true - 1) < 0.05
    want = p["noise"]["arw_dps_rthz"] * np.sqrt((tau + d) / (tau * T))
    assert abs(p["predicted_sigma_dps"] / want - 1) < 0.1
    with pytest.raises(ValueError):
        gyroflip.plan(0.4, static=y)  # no rate
    with pytest.raises(ValueError):
        gyroflip.plan(0.4)  # no noise source


def test_heading_agrees_with_the_cli(exe, tmp_path):
    """gyroflip.heading gives what `gyroflip heading --json` prints (docs/NORTH.md), and refuses
    a two-position run."""
    rec = tmp_path / "north.csv"
    run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 900, "--table-axis", "up",
        "--azimuth", 25, "--positions", "0,90,180,270", "--seed", 4, "-o", rec)
    cli = json.loads(run(exe, "heading", rec, "--latitude", 42.6, "--json"))
    py = gyroflip.heading([rec], 42.6)
    for key in ("heading_deg", "sigma_deg", "limit_deg", "ratio_to_limit", "scheme"):
        assert py[key] == cli[key], key
    assert py["schema"] == "gyroflip.heading/1"
    pair = tmp_path / "pair.csv"
    run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 120, "-o", pair)
    with pytest.raises(ValueError):
        gyroflip.heading([pair], 42.6)


def test_simulate_takes_the_north_finding_options_as_the_cli(exe, tmp_path):
    """gyroflip.simulate(positions, order, azimuth, table_axis, tilt_mrad, tilt_azimuth) gives the
    rows `gyroflip simulate` writes with the same options (issue 33), and its Earth truth is
    W_E cos(lat) cos(azimuth - angle) at each position (table axis up, level)."""
    out = tmp_path / "north.csv"
    run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 120, "--seed", 7, "--table-axis",
        "up", "--azimuth", 35, "--positions", "0,90,180,270", "--order", "cycle", "--tilt-mrad",
        0.5, "--tilt-azimuth", 20, "-o", out)
    rows = gyroflip.read_recording(out)
    s = gyroflip.simulate("hz1-90-100a", duration_s=120, seed=7, table_axis="up", azimuth=35,
                          positions=[0, 90, 180, 270], order="cycle", tilt_mrad=0.5,
                          tilt_azimuth=20)
    for key in ["time_s", "angle_deg", "rate_dps", "temp_c", "n_avg"]:
        np.testing.assert_array_equal(rows[key], s[key], err_msg=key)
    assert list(np.unique(s["angle_deg"])) == [0, 90, 180, 270]
    level = gyroflip.simulate("hz1-90-100a", duration_s=60, seed=7, table_axis="up", azimuth=35,
                              positions=[0, 90, 180, 270])
    # The horizontal Earth rate's contrast between opposite positions (the preset's cross-axis
    # sensitivity adds the same share of the vertical rate at every position).
    w_h = 7.292115e-5 * 180 / np.pi * np.cos(np.radians(42.6))
    e, a = level["earth_dps"], level["angle_deg"]
    for theta in (0, 90):
        half = (e[a == theta].mean() - e[a == theta + 180].mean()) / 2
        assert half == pytest.approx(w_h * np.cos(np.radians(35 - theta)), rel=1e-4), theta
    # the sweep by default for more than two positions: 0,90,180,270,270,180,90,0
    assert list(level["angle_deg"][:8]) == [0, 90, 180, 270, 270, 180, 90, 0]
    with pytest.raises(ValueError):
        gyroflip.simulate("hz1-90-100a", duration_s=10, order="random")
    with pytest.raises(ValueError):
        gyroflip.simulate("hz1-90-100a", duration_s=10, azimuth=10, axis="east")


def test_plan_and_heading_variants_agree_with_the_cli(exe, tmp_path):
    """gyroflip.plan(positions=..., heading=True, latitude=...) and gyroflip.heading(harmonics=2)
    and on a 0/180 run give what the CLI prints."""
    cli = json.loads(run(exe, "plan", "--sensor", "adxrs150", "--dead-time", 0.3, "--heading",
                         "--latitude", 42.6, "--json"))
    py = gyroflip.plan(0.3, sensor="adxrs150", heading=True, latitude=42.6)
    assert py["dwell_s"] == cli["dwell_s"]
    assert py["heading"]["predicted_sigma_deg"] == cli["heading"]["predicted_sigma_deg"]
    cli5 = json.loads(run(exe, "plan", "--sensor", "adxrs150", "--dead-time", 0.3, "--positions",
                          "0,72,144,216,288", "--json"))
    py5 = gyroflip.plan(0.3, sensor="adxrs150", positions=[0, 72, 144, 216, 288])
    assert py5["dwell_s"] == cli5["dwell_s"] and len(py5["visiting_order_deg"]) == 10
    with pytest.raises(ValueError):
        gyroflip.plan(0.3, sensor="adxrs150", heading=True)
    flip = tmp_path / "flip.csv"
    run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 600, "--table-axis", "up",
        "--azimuth", 70, "--positions", "0,180", "--seed", 4, "-o", flip)
    c = json.loads(run(exe, "heading", flip, "--latitude", 42.6, "--json"))
    p = gyroflip.heading([flip], 42.6)
    assert p["ambiguous"] and p["heading_mirror_deg"] == c["heading_mirror_deg"]
    five = tmp_path / "five.csv"
    run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 600, "--table-axis", "up",
        "--azimuth", 70, "--positions", "0,72,144,216,288", "--seed", 4, "-o", five)
    c2 = json.loads(run(exe, "heading", five, "--latitude", 42.6, "--harmonics", 2, "--json"))
    p2 = gyroflip.heading([five], 42.6, harmonics=2)
    assert p2["heading_deg"] == c2["heading_deg"]
    assert p2["second_harmonic_dps"] == c2["second_harmonic_dps"]


def test_calibrate_harmonic_terms_agree_with_the_cli(exe, tmp_path):
    """gyroflip.calibrate(..., pairing="harmonic") on a recording's columns carries the named terms,
    their covariance and the separability report, number for number as `gyroflip calibrate
    --pairing harmonic --json` of the file (issue 33)."""
    rec = tmp_path / "four.csv"
    run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 900, "--table-axis", "up",
        "--azimuth", 25, "--positions", "0,90,180,270", "--seed", 6, "-o", rec)
    cli = json.loads(run(exe, "calibrate", rec, "--pairing", "harmonic", "--json"))
    c = gyroflip.read_recording(rec)
    py = gyroflip.calibrate(c["time_s"], c["angle_deg"], c["rate_dps"], c["temp_c"], c["n_avg"],
                            pairing="harmonic", table_axis="up", positions_deg=c["positions_deg"])
    assert [t["name"] for t in py["terms"]] == ["b", "c1", "s1", "c2"]
    assert py["terms"] == cli["terms"]
    assert py["terms_covariance"] == cli["terms_covariance"]
    assert py["separability"] == cli["separability"]
    assert py["separability"]["table_axis"] == "vertical"


def test_plan_order_and_two_zero_one_eighty_headings_agree_with_the_cli(exe, tmp_path):
    """gyroflip.plan(order=...) is `plan --order` (issue 33), and gyroflip.heading of two 0/180 runs
    at two base azimuths is `heading RUN1 RUN2`."""
    for order in ("there-and-back", "cycle", "sweep"):
        cli = json.loads(run(exe, "plan", "--sensor", "adxrs150", "--dead-time", 0.3, "--positions",
                             "0,90,180,270", "--order", order, "--json"))
        py = gyroflip.plan(0.3, sensor="adxrs150", positions=[0, 90, 180, 270], order=order)
        for key in ("dwell_s", "period_s", "predicted_sigma_dps", "visiting_order_deg", "order"):
            assert py[key] == cli[key], (order, key)
        assert py["order"] == order
    assert gyroflip.plan(0.3, sensor="adxrs150", positions=[0, 90, 180, 270],
                         order="there-and-back")["visiting_order_deg"] == [0, 90, 180, 270, 180, 90]
    with pytest.raises(ValueError):
        gyroflip.plan(0.3, sensor="adxrs150", positions=[0, 180], order="sweep")
    runs = []
    for name, azimuth, seed in (("a.csv", 100, 1), ("b.csv", 190, 2)):
        path = tmp_path / name
        run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 600, "--table-axis", "up",
            "--azimuth", azimuth, "--positions", "0,180", "--seed", seed, "-o", path)
        runs.append(path)
    cli = json.loads(run(exe, "heading", *runs, "--latitude", 42.6, "--json"))
    py = gyroflip.heading(runs, 42.6)
    assert py == cli
    assert py["ambiguous"] and py["two_azimuths"] and py["base_turn_deg"] == 90


def test_compensate_applies_a_harmonic_calibration_as_the_cli(exe, tmp_path):
    """gyroflip.compensate with a harmonic calibration (issue 33) applies its terms as `gyroflip
    compensate --calibration`: on a four-position run at each position, on a 90/270 pair its
    c1 cos 90 + s1 sin 90 = s1, number for number (before, Python refused both: the harmonic
    pairing on the default 0/180 table)."""
    cal_csv, cal_json = tmp_path / "cal4.csv", tmp_path / "cal.json"
    run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 1200, "--seed", 21,
        "--positions", "0,90,180,270", "--latitude", -42.6, "--axis", "north", "-o", cal_csv)
    run(exe, "calibrate", cal_csv, "--pairing", "harmonic", "-o", cal_json)
    c = gyroflip.read_recording(cal_csv)
    py_cal = gyroflip.calibrate(c["time_s"], c["angle_deg"], c["rate_dps"], c["temp_c"], c["n_avg"],
                                pairing="harmonic", positions_deg=c["positions_deg"])
    for positions, seed, pairing in (("90,270", 22, "abba"), ("0,90,180,270", 23, "harmonic")):
        path = tmp_path / f"run{seed}.csv"
        run(exe, "simulate", "--sensor", "hz1-90-100a", "--duration", 600, "--seed", seed,
            "--positions", positions, "--latitude", -42.6, "--axis", "north", "-o", path)
        cli = json.loads(run(exe, "compensate", path, "--calibration", cal_json, "--json"))
        r = gyroflip.read_recording(path)
        for calibration in (cal_json, py_cal):
            py = gyroflip.compensate(r["time_s"], r["angle_deg"], r["rate_dps"], r["temp_c"],
                                     r["n_avg"], calibration=calibration,
                                     positions_deg=r["positions_deg"])
            assert py["summary"]["pairing"] == pairing
            assert py["applied"].startswith("at ")
            for key in ("cycles", "mean_dps", "std_dps", "stderr_correlated_dps", "drift_dps"):
                assert py["summary"][key] == cli[key], (positions, key)
            assert py["summary"]["delta_n"]["coeffs_dps"] == cli["delta_n"]["coeffs_dps"]
            assert py["summary"]["delta_n"]["terms_dps"] == cli["delta_n"]["terms_dps"]
            if calibration is cal_json:
                for key in ("error_dps", "new_power_up_dps"):
                    assert py["summary"]["delta_n"][key] == cli["delta_n"][key], (positions, key)


def test_sensors_and_separability_agree_with_the_cli(exe):
    """gyroflip.sensors and gyroflip.separability are `sensors --json` and `calibrate --explain
    --positions --json` (issue 33 item 5: Python has each function; before, neither existed)."""
    assert gyroflip.sensors() == json.loads(run(exe, "sensors", "--json"))
    assert gyroflip.sensors(0.1, -30) == json.loads(run(exe, "sensors", "--dead-time", 0.1,
                                                        "--latitude", -30, "--json"))
    for positions, axis in (("0,90,180,270", None), ("0,120,240", "up"), ("0,180", None)):
        args = ["calibrate", "--explain", "--positions", positions, "--json"]
        if axis:
            args[4:4] = ["--table-axis", axis]
        cli = json.loads(run(exe, *args))
        assert gyroflip.separability([float(a) for a in positions.split(",")], axis) == cli
    with pytest.raises(ValueError):
        gyroflip.sensors(-1)
