"""Catalogue subsets, the committed catalogue.md, and the `gaitml features` command."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.features import CATALOGUE, FEATURE_SETS, feature_names
from gaitml.features._catalogue import catalogue_markdown
from gaitml.features._catalogue import main as catalogue_main
from gaitml.io import write_gaitml_csv
from gaitml.recording import Recording

ROOT = Path(__file__).resolve().parents[2]


def test_paper34_is_table1():
    nums = [s.number for s in CATALOGUE if s.name in FEATURE_SETS["paper34"]]
    table1 = {  # paper 003 Table 1, per mode (right side step lists 35 twice)
        "walk": [5, 9, 12, 19, 20, 49, 50],
        "run": [5, 8, 9, 10, 11, 12, 15, 16, 23, 24, 27, 28, 31, 32, 47, 48, 49, 52],
        "side_left": [9, 29, 33, 34, 42, 45, 49],
        "side_right": [9, 13, 30, 34, 35, 36, 38, 40, 41, 42, 35, 47, 49],
        "backward": [5, 9, 19, 20, 26, 29, 49, 50],
    }
    union = sorted(set().union(*map(set, table1.values())))
    assert nums == union and len(nums) == 34


def test_subsets():
    assert len(feature_names("all52")) == 52 and feature_names("all") == feature_names("all52")
    gy = feature_names("all52+gyro")
    assert len(gy) == 104 and gy[:52] == feature_names("all52") and gy[52] == "gyr_x__mean" and gy[-1] == "gyr_x__f1"


def test_committed_catalogue_is_up_to_date(tmp_path):
    committed = (ROOT / "features" / "catalogue.md").read_text(encoding="utf-8")
    assert committed == catalogue_markdown(), "regenerate: python -m gaitml.features.catalogue --out features/catalogue.md"
    out = tmp_path / "c.md"
    assert catalogue_main(["--out", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == committed
    assert sum(line.startswith("| F") and line[3].isdigit() for line in committed.splitlines()) == 52


def _csv(tmp_path, n=400, gyro=True) -> Path:
    rng = np.random.default_rng(0)
    acc = rng.normal(0, 1, (n, 3)) + [0, 0, 9.8]
    labels = np.array(["walk"] * (n // 2) + ["run"] * (n - n // 2))
    rec = Recording.from_arrays(acc, 50.0, gyr=rng.normal(0, 1, (n, 3)) if gyro else None, labels=labels, meta={"id": "r1"})
    path = tmp_path / "r1.csv"
    write_gaitml_csv(rec, path)
    return path


def test_cli_writes_table(tmp_path):
    path = _csv(tmp_path)
    out = tmp_path / "f.csv"
    assert main(["features", str(path), "--subset", "paper34", "--window-s", "1.0", "--overlap", "0.5", "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert list(df.columns[:6]) == ["start", "end", "t_start_s", "t_end_s", "label", "label_fraction"]
    assert list(df.columns[6:]) == feature_names("paper34")
    assert (df["end"] - df["start"] == 50).all() and len(df) == (400 - 50) // 25 + 1
    assert main(["features", str(path), "--subset", "all52+gyro", "--out", str(out)]) == 0
    assert pd.read_csv(out).shape[1] == 6 + 104


def test_cli_summary_and_errors(tmp_path, capsys):
    path = _csv(tmp_path, gyro=False)
    assert main(["features", str(path)]) == 0
    text = capsys.readouterr().out
    assert "windows: 9 of 75 samples" in text and "F52" in text and "acc_x__f1" in text
    assert main(["features", str(path), "--window-s", "10"]) == 2
    err = capsys.readouterr().err
    assert "500 samples (10 s" in err and len(err.strip().splitlines()) == 1
    assert main(["features", str(path), "--subset", "all52+gyro"]) == 2
    assert "gyroscope" in capsys.readouterr().err
    assert main(["features", str(path), "--subset", "nope"]) == 2


@pytest.mark.parametrize("name", ["all52", "paper34"])
def test_real_recording_features_are_finite(name):
    from gaitml.features import extract_features
    from gaitml.io import read_recording
    from tests.conftest import shared

    rec = read_recording(shared("ifsm-flat-phone", "acceleration_flat_holding_1.xlsx"))
    f = extract_features(rec, subset=name)
    assert len(f) > 100 and np.isfinite(f.to_numpy()).all()
    # flat-held phone while walking: z carries gravity, the gravity-free magnitude varies by a few m/s^2
    assert 1.0 < f["acc_mag__mean_abs"].median() < 5.0
    assert (f["acc_x__var"] > 0).all() and (f["acc_mag__var"] > 0.5).median()
