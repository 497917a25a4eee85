"""Issue 28 finding 9: every message that names a flag is a fix that works when applied.

Each case: an input, the command that refuses it (exit 2, the message naming a flag), and the
same command with that flag, which must then succeed (exit 0).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from tests.conftest import ROOT
from tests.io_apps._make import PHY_ACC, PHY_GYR, acc_true, gyr_true, jittered_times, sensor_logger_export, write_csv

G = 9.80665


def _walk_csv(path, *, acc_scale=1.0, gyr_scale=1.0, fs=100.0, seconds=30.0):
    t = np.arange(0, seconds, 1 / fs)
    acc = np.column_stack([0.6 * np.sin(2 * np.pi * t), 0.3 * np.cos(2 * np.pi * 2 * t), 9.81 + 3 * np.sin(2 * np.pi * 2 * t)])
    gyr = np.column_stack([0.8 * np.sin(2 * np.pi * t), 0.4 * np.cos(2 * np.pi * 2 * t), 0.2 * np.sin(t)])
    df = pd.DataFrame(
        np.column_stack([t, acc * acc_scale, gyr * gyr_scale]), columns=["t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]
    )
    df.to_csv(path, index=False)
    return path


def _phyphox_in_g(folder):
    """A phyphox export whose header says m/s^2 over values in g (the issue's case)."""
    ta = jittered_times(0.0, 30.0, 100.0, seed=1)
    a = acc_true(ta) / G
    write_csv(folder / "Accelerometer.csv", PHY_ACC, [ta, *a.T, np.linalg.norm(a, axis=1)])
    tg = jittered_times(0.0, 30.0, 100.0, seed=2)
    g = gyr_true(tg)
    write_csv(folder / "Gyroscope.csv", PHY_GYR, [tg, *g.T, np.linalg.norm(g, axis=1)])
    return folder


def _phyphox_gyr_deg(folder):
    ta = jittered_times(0.0, 30.0, 100.0, seed=1)
    a = acc_true(ta)
    write_csv(folder / "Accelerometer.csv", PHY_ACC, [ta, *a.T, np.linalg.norm(a, axis=1)])
    tg = jittered_times(0.0, 30.0, 100.0, seed=2)
    g = np.degrees(gyr_true(tg)) * 30
    write_csv(folder / "Gyroscope.csv", PHY_GYR, [tg, *g.T, np.linalg.norm(g, axis=1)])
    return folder


def _fast(path):
    t = np.arange(0, 3, 1 / 20_000)
    df = pd.DataFrame({"t": t, "acc_x": 0.1, "acc_y": 0.2, "acc_z": 9.81 + np.sin(2 * np.pi * 2 * t)})
    df.to_csv(path, index=False)
    return path


def _bom_toml(tmp_path):
    src = ROOT / "experiments"
    cfg = next(iter(sorted(src.glob("*.toml")))) if src.exists() else None
    if cfg is None:
        pytest.skip("no experiment config to copy")
    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + cfg.read_bytes())
    return p


CASES = {
    # name: (make input, failing argv, pattern naming the flag, the flag's arguments)
    "gaitml-csv acc in g": (lambda d: _walk_csv(d / "g.csv", acc_scale=1 / G), ["info", "{inp}"], "--acc-unit g", ["--acc-unit", "g"]),
    "gaitml-csv gyr in deg/s": (
        lambda d: _walk_csv(d / "d.csv", gyr_scale=np.degrees(1.0)),
        ["info", "{inp}"],
        "--gyr-unit deg/s",
        ["--gyr-unit", "deg/s"],
    ),
    "phyphox acc in g": (lambda d: _phyphox_in_g(d / "phy"), ["info", "{inp}"], "--acc-unit g", ["--acc-unit", "g"]),
    "phyphox gyr in deg/s": (lambda d: _phyphox_gyr_deg(d / "phy"), ["info", "{inp}"], "--gyr-unit deg/s", ["--gyr-unit", "deg/s"]),
    "20 kHz timestamps": (lambda d: _fast(d / "fast.csv"), ["info", "{inp}"], "--sampling-rate-hz", ["--sampling-rate-hz", "100"]),
    "short file, long windows": (lambda d: _walk_csv(d / "s.csv", seconds=1.0), ["features", "{inp}"], "--window-s", ["--window-s", "0.5"]),
    "pdr --modes model without a model": (
        lambda d: _walk_csv(d / "w.csv"),
        ["pdr", "{inp}", "--modes", "model"],
        "--modes true",
        ["--model", str(ROOT / "models" / "demo")],
    ),
}


@pytest.mark.parametrize("name", list(CASES))
def test_the_named_fix_changes_the_outcome(name, tmp_path, capsys):
    make, argv, pattern, fix = CASES[name]
    inp = make(tmp_path)
    argv = [a.format(inp=inp) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert pattern in err, err
    code = main(argv + fix)
    err = capsys.readouterr().err
    assert code == 0, err


def test_info_format_is_obeyed(tmp_path, capsys):
    d = sensor_logger_export(tmp_path / "2023-11-14_22-13-20", platform="Android")
    assert main(["info", str(d), "--format", "sensor-logger", "--json"]) == 0
    import json

    js = json.loads(capsys.readouterr().out)
    assert js["kind"] == "recording" and js["format"] == "sensor-logger"
    # the format is what is asked for, not a guess: the wrong one is refused
    assert main(["info", str(d), "--format", "phyphox"]) == 2


def test_toml_config_with_a_bom_is_read(tmp_path, capsys):
    from gaitml.pipeline.config import load_config

    p = _bom_toml(tmp_path)
    load_config(p, check_paths=False)
