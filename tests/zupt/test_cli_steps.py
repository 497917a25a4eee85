"""`gaitml zupt` (DESIGN sec. 5 contract) and the zupt-magnitude step detector (paper 004)."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.consts import GRAVITY_MS2
from gaitml.io import write_gaitml_csv
from gaitml.recording import Recording
from gaitml.steps.zupt_magnitude import ZuptMagnitudeStepDetector, steps_from_zupts
from tests.conftest import shared
from tests.synthetic import synthetic_foot_walk


@pytest.fixture
def walk_csv(tmp_path):
    p = tmp_path / "walk.csv"
    write_gaitml_csv(synthetic_foot_walk(2050), p)  # 20.5 strides of 1 s, stance first
    return p


def test_cli_json_contract(walk_csv, capsys):
    assert main(["zupt", str(walk_csv), "--json"]) == 0
    out = capsys.readouterr().out.strip().splitlines()
    assert len(out) == 1
    obj = json.loads(out[0])
    assert {"n_intervals", "intervals", "zero_velocity_fraction"} <= set(obj)
    assert obj["n_intervals"] == len(obj["intervals"]) == 21  # one stance per 1 s stride
    assert set(obj["intervals"][0]) == {"t_start_s", "t_end_s"}
    assert 0.4 < obj["zero_velocity_fraction"] < 0.7
    assert obj["detector"] == "pseudo-std"


def test_cli_out_and_threshold(walk_csv, tmp_path, capsys):
    out = tmp_path / "z.csv"
    assert main(["zupt", str(walk_csv), "--detector", "pseudo-std", "--threshold-rads", "0.05", "--out", str(out), "--json"]) == 0
    obj = json.loads(capsys.readouterr().out)
    table = pd.read_csv(out)
    assert list(table.columns) == ["start", "end", "t_start_s", "t_end_s"]
    assert len(table) == obj["n_intervals"]
    assert obj["threshold_rads"] == 0.05
    assert not list(tmp_path.glob("*.tmp*"))


@pytest.mark.parametrize("name", ["magnitude", "gyro-range", "magnitude-std", "shoe"])
def test_cli_every_detector(walk_csv, capsys, name):
    assert main(["zupt", str(walk_csv), "--detector", name]) == 0
    assert "zero-velocity intervals" in capsys.readouterr().out


def test_cli_bad_input_exit_2(walk_csv, tmp_path, capsys):
    assert main(["zupt", str(walk_csv), "--detector", "shoe", "--threshold-rads", "1"]) == 2
    assert main(["zupt", str(walk_csv), "--threshold-rads", "-1"]) == 2
    nogyr = tmp_path / "nogyr.csv"
    write_gaitml_csv(Recording(acc=np.tile([0, 0, GRAVITY_MS2], (300, 1)), sampling_rate_hz=100.0), nogyr)
    assert main(["zupt", str(nogyr)]) == 2
    err = capsys.readouterr().err
    assert "needs a gyroscope" in err and "Traceback" not in err
    assert main(["zupt", str(nogyr), "--detector", "magnitude", "--json"]) == 0


def test_cli_gaitmap_evaluation(capsys):
    path = shared("gaitmap-example", "imu_sample.csv.gz")
    assert main(["zupt", str(path), "--sensor", "right", "--json"]) == 0
    ev = json.loads(capsys.readouterr().out)["evaluation"]
    assert ev["n_strides"] == 29 and ev["min_vel_recall"] >= 0.95


def test_zupt_magnitude_counts_one_step_per_stance():
    rec = synthetic_foot_walk(3000)  # 30 strides of 1 s, stance first
    det = ZuptMagnitudeStepDetector().detect(rec)
    assert det.detect(rec) is det
    assert len(det.steps_) == 29  # the first stance starts at sample 0: no landing observed
    assert det.steps_.attrs["event"] == "t_start_s"
    np.testing.assert_allclose(det.steps_["period_s"], 1.0, atol=0.05)
    assert len(ZuptMagnitudeStepDetector(count_leading=True).detect(rec).steps_) == 30


def test_steps_from_zupts_columns():
    z = pd.DataFrame({"start": [10, 110], "end": [40, 150]})
    st = steps_from_zupts(z, 100.0)
    assert st["peak"].tolist() == [24, 129]
    assert st["period_s"].tolist() == [1.0, 1.0]
    assert st["duration_s"].tolist() == [0.3, 0.4]
    assert len(steps_from_zupts(z.iloc[:0], 100.0)) == 0


def test_steps_registry_resolves_zupt_magnitude():
    from gaitml.steps import get_detector

    assert isinstance(get_detector("zupt-magnitude"), ZuptMagnitudeStepDetector)


def test_cli_large_input_path_equals_whole_file(walk_csv, capsys, monkeypatch):
    assert main(["zupt", str(walk_csv), "--json"]) == 0
    whole = json.loads(capsys.readouterr().out)
    import gaitml.io.chunked

    monkeypatch.setattr(gaitml.io.chunked, "LARGE_INPUT_SAMPLES", 10)
    assert main(["zupt", str(walk_csv), "--json"]) == 0
    chunked = json.loads(capsys.readouterr().out)
    assert chunked["intervals"] == whole["intervals"]
    assert chunked["zero_velocity_fraction"] == whole["zero_velocity_fraction"]


@pytest.mark.parametrize("name", ["pseudo-std", "magnitude", "gyro-range", "magnitude-std", "shoe"])
def test_chunked_detection_equals_whole_file(walk_csv, name):
    from gaitml.chunked_run import long_zupts
    from gaitml.io import read_recording
    from gaitml.zupt import get_detector

    mask, table, fs = long_zupts(walk_csv, name, chunk_s=5.0, margin_s=2.0, progress=False)
    whole = get_detector(name).detect(read_recording(walk_csv))
    np.testing.assert_array_equal(mask, whole.per_sample_zupts_)
    assert table[["start", "end"]].equals(whole.zupts_[["start", "end"]])
