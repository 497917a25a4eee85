"""data.source = "folder" with a manifest of phone-app exports: gaitml evaluate end to end, one-line errors."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pandas as pd
import pytest

from experiments.scripts.phone_demo import write_columns_csv, write_intervals, write_phone_folder
from gaitml.cli import main
from gaitml.pipeline import parse_config, prepare_data
from gaitml.simulate import simulate_dataset

CONFIG = """
name = "phones"
[data]
source = "folder"
path = "phones"
[windows]
by = "{by}"
[cv]
n_jobs = 1
"""


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("phones")
    # unpacked phyphox and Sensor Logger folders and a column-mapped CSV, each with an intervals file
    write_phone_folder(d / "phones", subjects=3, duration_s=30.0, seed=4, zip_exports=False)
    return d


def _copy(folder, tmp_path):
    shutil.copytree(folder / "phones", tmp_path / "phones")
    return tmp_path


def _evaluate(d, by, capsys):
    (d / "cfg.toml").write_text(CONFIG.format(by=by))
    capsys.readouterr()
    code = main(["evaluate", str(d / "cfg.toml"), "--out", str(d / f"run-{by}"), "--json"])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("by", ["time", "steps"])
def test_gaitml_evaluate_reads_a_folder_of_phone_exports(folder, by, capsys):
    code, out, err = _evaluate(folder, by, capsys)
    assert code == 0, err
    res = json.loads(out)
    assert res["n_recordings"] == 3 and res["n_groups"] == 3 and len(res["folds"]) == 3
    assert any("manifest manifest.csv: 3 recordings (columns-csv, phyphox, sensor-logger)" in n for n in res["notes"])
    assert any("from intervals files" in n for n in res["notes"])
    assert set(res["labels"]) <= {"walk", "run", "side_left", "side_right", "backward"}


def test_recordings_match_the_simulation_and_labels_the_truth(folder):
    cfg = parse_config({"name": "x", "data": {"source": "folder", "path": str(folder / "phones")}})
    data = prepare_data(cfg, use_cache=False)
    sims = simulate_dataset(n_subjects=3, duration_s=30.0, seed=4, sampling_rate_hz=50.0, segment_s=(6.0, 9.0))
    assert [r.meta["subject"] for r in data.recordings] == ["alice", "bob", "carol"] == data.groups
    assert [r.meta["format"] for r in data.recordings] == ["phyphox", "sensor-logger", "columns-csv"]
    for r, s in zip(data.recordings, sims, strict=True):
        n = min(r.n_samples, s.n_samples)
        assert n >= s.n_samples - 1
        np.testing.assert_allclose(r.acc[:n], s.acc[:n], atol=2e-3 * 9.81)  # 5 significant digits, g -> m/s^2
        np.testing.assert_allclose(r.gyr[:n], s.gyr[:n], atol=1e-3)
        assert np.mean(r.labels[:n] == s.labels[:n]) > 0.98  # +-0.3 s hand-written boundaries snapped to steps
        assert r.meta["position"] == "hand"


def test_samples_outside_every_interval_are_left_out_not_a_class(folder, tmp_path, capsys):
    d = _copy(folder, tmp_path)
    iv = pd.read_csv(d / "phones" / "carol.intervals.csv")
    iv = iv.iloc[1:]  # the first stretch of carol's walk is not annotated
    iv.to_csv(d / "phones" / "carol.intervals.csv", index=False)
    cfg = parse_config({"name": "x", "data": {"source": "folder", "path": str(d / "phones")}})
    data = prepare_data(cfg, use_cache=False)
    assert "unlabelled" in set(data.recordings[2].labels)
    assert data.keep_labels is not None and "unlabelled" not in data.keep_labels
    code, out, err = _evaluate(d, "time", capsys)
    assert code == 0, err
    assert "unlabelled" not in json.loads(out)["labels"]


@pytest.mark.parametrize(
    "edit, match",
    [
        (lambda m, d: m.drop(columns=["subject"]), r"manifest.csv has no 'subject' column"),
        (
            lambda m, d: m.assign(file=["alice-phyphox", "nobody.csv", "carol.csv"]),
            r"manifest.csv line 3 names nobody.csv, which does not exist",
        ),
        (
            lambda m, d: m.assign(intervals=["alice.intervals.csv", "gone.txt", "carol.intervals.csv"]),
            r"line 3 \(bob-sensorlogger\) names the intervals file gone.txt",
        ),
        (
            lambda m, d: m.assign(intervals=["alice.intervals.csv", "bob.labels.txt", ""]),
            r"line 4: recording carol.csv has no labels; give it an intervals file",
        ),
        (lambda m, d: m.assign(format=["phyphox", "sensor-logger", "excel"]), r"line 4 \(carol.csv\) has format 'excel'"),
        (lambda m, d: m.assign(columns=["", "", "t=time_ms,acc_x=nope,acc_y=ay_g,acc_z=az_g"]), r"line 4 \(carol.csv\): .*nope"),
    ],
    ids=["no-subject", "missing-file", "missing-intervals", "no-labels", "bad-format", "bad-columns"],
)
def test_manifest_problems_are_one_line_errors(folder, tmp_path, capsys, edit, match):
    d = _copy(folder, tmp_path)
    man = pd.read_csv(d / "phones" / "manifest.csv", dtype=str, keep_default_na=False)
    edit(man, d).to_csv(d / "phones" / "manifest.csv", index=False)
    code, out, err = _evaluate(d, "time", capsys)
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gaitml: error:"), err
    import re

    assert re.search(match, lines[0]), lines[0]
    assert not (d / "run-time").exists()  # no partial run folder


def test_a_folder_of_app_exports_without_a_manifest_is_a_one_line_error(tmp_path, capsys):
    d = tmp_path / "phones"
    rec = simulate_dataset(n_subjects=1, duration_s=20.0, seed=1)[0]
    write_columns_csv(rec, d / "a.csv")  # a CSV no reader recognises without its column map
    write_intervals(rec, d / "a.intervals.csv")
    code, out, err = _evaluate(tmp_path, "time", capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    (tmp_path / "cfg.toml").write_text(CONFIG.format(by="time").replace('path = "phones"', 'path = "phones"\nmanifest = "manifest.csv"'))
    assert main(["evaluate", str(tmp_path / "cfg.toml"), "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "data.manifest = 'manifest.csv' is not a file" in err
