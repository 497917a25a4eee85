"""Issue 28 finding 5: a phone lying still is `still`, never one of the five motion modes."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd

from gaitml.cli import main
from gaitml.io import read_recording
from gaitml.models import load_model, predict_recording
from tests.conftest import ROOT

MODES = {"walk", "run", "side_left", "side_right", "backward"}


def _still_csv(path, seconds=60.0, fs=50.0):
    rng = np.random.default_rng(3)
    n = int(seconds * fs)
    acc = np.column_stack([np.zeros(n), np.zeros(n), np.full(n, 9.80665)]) + rng.normal(0, 0.02, (n, 3))
    gyr = rng.normal(0, 0.002, (n, 3))
    df = pd.DataFrame(np.column_stack([np.arange(n) / fs, acc, gyr]), columns=["t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"])
    df.to_csv(path, index=False)
    return path


def test_lying_still_is_still_in_the_table_json_and_stderr(tmp_path, capsys):
    p = _still_csv(tmp_path / "table.csv")
    out = tmp_path / "pred.csv"
    assert main(["predict", str(ROOT / "models" / "demo"), str(p), "--json", "--out", str(out)]) == 0
    captured = capsys.readouterr()
    js = json.loads(captured.out)
    modes = {w["mode"] for w in js["windows"]}
    assert modes == {"still"}, modes  # was backward on every window
    assert js["still_fraction"] == 1.0 and js["counts"] == {"still": len(js["windows"])}
    assert sum("reported as 'still'" in line for line in captured.err.splitlines()) == 1
    table = pd.read_csv(out)
    assert (table["mode"] == "still").all() and table["still"].all()


def test_walking_windows_are_not_still():
    rec = read_recording(ROOT / "data" / "samples" / "S01-walk.csv")
    table = predict_recording(load_model(ROOT / "models" / "demo"), rec)
    inner = table.iloc[1:-1]
    assert not inner["still"].any() and set(inner["mode"]) <= MODES
