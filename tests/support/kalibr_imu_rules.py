"""Reads a Kalibr IMU file with the rules of Kalibr's own reader (ethz-asl/kalibr,
aslam_offline_calibration/kalibr/python/kalibr_common/ConfigReader.py, class ImuParameters):
yaml.safe_load; every key its getters read must be there (a KeyError becomes "Field ... missing");
rostopic a str (checkRosTopic); update_rate > 0 (checkUpdateRate); each noise density and random
walk > 0 (checkAccelerometerStatistics, checkGyroStatistics); the discrete-time density it
derives, density / sqrt(1 / update_rate), computed as it does. Stricter than Kalibr where Kalibr
would fail later or compare across types: the numbers must be int or float (not bool, not str)
and finite.

Usage: python3 kalibr_imu_rules.py IMU.yaml [OUT.json] -> exit 0 and the values as JSON, or
exit 1 with the rule broken. Also importable: check(path) -> dict."""
import json
import math
import sys

import yaml

REQUIRED = ("rostopic", "update_rate", "accelerometer_noise_density", "accelerometer_random_walk",
            "gyroscope_noise_density", "gyroscope_random_walk")


def _number(data, key):
    v = data[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ValueError(f"{key} is not a number: {v!r} ({type(v).__name__})")
    if not math.isfinite(v):
        raise ValueError(f"{key} is not finite: {v!r}")
    return v


def check(path):
    with open(path, "r") as f:
        data = yaml.safe_load(f)
    if not isinstance(data, dict):
        raise ValueError("the file is not a YAML mapping")
    for key in REQUIRED:
        if key not in data:
            raise ValueError(f"Field '{key}' missing in file: {path}")
    if not isinstance(data["rostopic"], str):
        raise ValueError("rostopic has to be a string")
    rate = _number(data, "update_rate")
    if rate <= 0.0:
        raise ValueError("invalid update_rate")
    out = {"rostopic": data["rostopic"], "update_rate": rate}
    for key in REQUIRED[2:]:
        v = _number(data, key)
        if v <= 0.0:
            raise ValueError(f"invalid {key}")
        out[key] = v
    # As Kalibr's getters: the discrete-time densities it derives from the update rate.
    out["accelerometer_noise_density_discrete"] = (
        out["accelerometer_noise_density"] / math.sqrt(1.0 / rate))
    out["gyroscope_noise_density_discrete"] = out["gyroscope_noise_density"] / math.sqrt(1.0 / rate)
    return out


if __name__ == "__main__":
    try:
        values = check(sys.argv[1])
    except (ValueError, KeyError, yaml.YAMLError) as e:
        print(f"[ImuConfig Reader]: {e}", file=sys.stderr)
        sys.exit(1)
    if len(sys.argv) > 2:
        with open(sys.argv[2], "w") as f:
            json.dump(values, f)
    sys.exit(0)
