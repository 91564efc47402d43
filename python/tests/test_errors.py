"""Bad input raises ValueError (data, arguments) or OSError (files) with the CLI's messages."""
import numpy as np
import pytest

import gyroflip


def test_non_finite_sample_names_it():
    y = np.ones(100)
    y[42] = np.nan
    with pytest.raises(ValueError, match=r"sample 42 \(0-based\) is not finite"):
        gyroflip.deviation(y)
    with pytest.raises(ValueError, match="sample 42"):
        gyroflip.oadev(y, data_type="freq")


@pytest.mark.parametrize("kwargs, match", [
    ({"rate": 0.0}, "rate must be a positive"),
    ({"rate": float("inf")}, "rate must be a positive"),
    ({"kind": "xdev"}, "unknown statistic 'xdev'"),
    ({"input": "voltage"}, "input must be 'rate' or 'angle'"),
    ({"ci": 1.5}, r"ci must lie in \(0, 1\)"),
    ({"taus": "weekly"}, "weekly"),
    ({"taus": [-1.0]}, "taus must be"),
])
def test_bad_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        gyroflip.deviation(np.ones(100), **kwargs)


def test_two_dimensional_data_is_refused():
    with pytest.raises(ValueError, match="1-D"):
        gyroflip.deviation(np.ones((10, 10)))


def test_too_short():
    with pytest.raises(ValueError):
        gyroflip.oadev([1.0], data_type="freq")


def test_bad_data_type():
    with pytest.raises(ValueError, match="data_type must be 'phase' or 'freq'"):
        gyroflip.adev(np.ones(10), data_type="angle")


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
