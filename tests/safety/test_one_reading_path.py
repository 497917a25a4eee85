"""Issue 28 finding 2: a file over the chunking threshold is read, validated and resampled as a small file is."""

from __future__ import annotations

import json
import re

import numpy as np
import pandas as pd
import pytest

import gaitml.io.chunked as ch
from gaitml.cli import main
from gaitml.io import read_recording

STEP_HZ = 2.0


def _walk(t: np.ndarray) -> np.ndarray:
    """A vertical bounce at 2 steps/s on top of gravity, with some sideways sway."""
    return np.column_stack(
        [0.6 * np.sin(np.pi * STEP_HZ * t), 0.3 * np.cos(np.pi * STEP_HZ * t), 9.81 + 3.0 * np.sin(2 * np.pi * STEP_HZ * t)]
    )


def _gyr(t: np.ndarray) -> np.ndarray:
    return np.column_stack([0.8 * np.sin(np.pi * STEP_HZ * t), 0.4 * np.cos(2 * np.pi * STEP_HZ * t), 0.2 * np.sin(np.pi * t / 7)])


def _write(path, t, *, gyr_scale=1.0, sep=",", decimal=".", labels=None):
    df = pd.DataFrame(
        np.column_stack([t, _walk(t), gyr_scale * _gyr(t)]), columns=["t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]
    )
    if labels is not None:
        df["label"] = labels
    df.to_csv(path, index=False, sep=sep, decimal=decimal, float_format="%.6f")
    return path


@pytest.fixture
def chunked(monkeypatch):
    """Every input goes the chunked road, read in blocks of 10,000 rows (so the first block is not the file)."""
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", -1)
    monkeypatch.setattr(ch, "_ROWS_PER_READ", 10_000)


def _json(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, (json.loads(out) if code == 0 and out.strip() else None), err


def test_rate_change_mid_file_is_judged_over_the_whole_file(tmp_path, capsys, chunked):
    # 100 s at 200 Hz (screen on), then 400 s at 100 Hz
    t = np.concatenate([np.arange(0, 100, 1 / 200), 100 + np.arange(0, 400, 1 / 100)])
    p = _write(tmp_path / "day.csv", t)
    code, js, err = _json(capsys, ["steps", str(p), "--json"])
    assert code == 0
    assert js["sampling_rate_hz"] == pytest.approx(100.0)  # the first block said 200 Hz
    # 2 steps per second for 500 s: the whole file counted (was about a third, at a doubled rate)
    assert abs(js["n_steps"] - STEP_HZ * 500) <= 0.02 * STEP_HZ * 500
    assert sum("rate changes mid-file" in line for line in err.splitlines()) == 1
    assert re.search(r"200 Hz from 0 to 1\d\d(\.\d+)? s against 100 Hz", err), err
    # features end where the file ends
    out = tmp_path / "f.csv"
    assert main(["features", str(p), "--out", str(out)]) == 0
    assert pd.read_csv(out)["t_end_s"].max() == pytest.approx(500.0, abs=1.6)


def test_the_same_rate_change_read_whole_is_reported_the_same(tmp_path):
    t = np.concatenate([np.arange(0, 100, 1 / 200), 100 + np.arange(0, 400, 1 / 100)])
    rec = read_recording(_write(tmp_path / "day.csv", t))
    scan = ch.scan_gaitml_csv(tmp_path / "day.csv", rows_per_read=10_000)
    assert rec.sampling_rate_hz == scan.sampling_rate_hz == pytest.approx(100.0)
    assert rec.meta["rate_changes"] == scan.meta["rate_changes"]
    assert rec.meta["rate_changes"][0][2] == pytest.approx(200.0, rel=0.01) and rec.meta["rate_changes"][0][1] == pytest.approx(100, abs=5)
    assert rec.meta["warnings"] == scan.warnings and "anti-alias" in rec.meta["resample_method"]
    assert rec.n_samples == scan.n_samples


def test_gyroscope_in_deg_s_is_refused_on_the_long_road(tmp_path, capsys, chunked):
    p = _write(tmp_path / "degs.csv", np.arange(0, 300, 1 / 100), gyr_scale=np.degrees(1.0) * 20)
    for command in (["zupt", str(p)], ["features", str(p), "--out", str(tmp_path / "f.csv")]):
        code, _, err = _json(capsys, command)
        assert code == 2 and "deg/s" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "f.csv").exists()
    # the fix it names works
    code, js, err = _json(capsys, ["zupt", str(p), "--gyr-unit", "deg/s", "--json"])
    assert code == 0


def test_semicolon_decimal_comma_is_read_on_the_long_road(tmp_path, capsys, chunked):
    t = np.arange(0, 300, 1 / 100)
    a = _write(tmp_path / "dot.csv", t)
    b = _write(tmp_path / "comma.csv", t, sep=";", decimal=",")
    code_a, js_a, _ = _json(capsys, ["steps", str(a), "--json"])
    code_b, js_b, err = _json(capsys, ["steps", str(b), "--json"])
    assert code_a == code_b == 0, err
    assert js_a["n_steps"] == js_b["n_steps"]


def test_empty_label_is_refused_on_the_long_road(tmp_path, capsys, chunked):
    t = np.arange(0, 300, 1 / 100)
    labels = np.array(["walk"] * len(t), dtype=object)
    labels[25_000] = ""
    p = _write(tmp_path / "lab.csv", t, labels=labels)
    code, _, err = _json(capsys, ["features", str(p), "--out", str(tmp_path / "f.csv")])
    assert code == 2 and "empty label at line 25002" in err
