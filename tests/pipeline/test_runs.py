"""End to end: each model kind on a tiny simulated set, run folders, CLI train/evaluate/predict contracts."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.models import load_model, predict_recording, torch_available
from gaitml.pipeline import evaluate_config, parse_config, train_config
from tests.models.synth import write_synth_folder

needs_torch = pytest.mark.skipif(not torch_available(), reason="torch extra not installed")

TINY = {"subjects": 3, "duration_s": 60.0, "modes": ["walk", "run", "side_left"]}


def _tiny_cfg(kind, params=None, **extra):
    raw = {
        "name": f"tiny-{kind}",
        "seed": 1,
        "data": {"source": "simulated", "simulated": TINY},
        "model": {"kind": kind, "params": params or {}},
    }
    for k, v in extra.items():
        raw.setdefault(k, {}).update(v)
    return parse_config(raw)


@pytest.mark.parametrize(
    ("kind", "params"),
    [
        ("linear-ovo-svm", {"C": 1.0}),
        pytest.param("mlp", {"epochs": 5}, marks=needs_torch),
        pytest.param("cnn1d", {"epochs": 3}, marks=needs_torch),
    ],
)
def test_each_model_kind_end_to_end_on_simulated_data(tmp_path, kind, params):
    cfg = _tiny_cfg(kind, params)
    res = evaluate_config(cfg, out_dir=tmp_path / "run", progress=False)
    assert res["model_kind"] == kind and len(res["folds"]) == 3
    assert 0.0 <= res["accuracy"] <= 1.0 and res["labels"] == ["walk", "run", "side_left"]
    chance = 1 / 3
    assert res["accuracy_before_correction"] > chance
    model = train_config(cfg, out_dir=tmp_path / "model", progress=False)
    loaded = load_model(tmp_path / "model")
    assert loaded.kind == kind and loaded.info["cv_scores"]["n_folds"] == 3
    from gaitml.simulate import simulate_dataset

    rec = simulate_dataset(n_subjects=1, duration_s=30.0, modes=("walk", "run", "side_left"), seed=99)[0]
    out = predict_recording(loaded, rec)
    assert len(out) > 10 and set(out["mode"]) <= set(model.labels)


def test_run_folder_contents_and_sweep(tmp_path):
    cfg = _tiny_cfg("linear-ovo-svm", sweep={})
    cfg = parse_config({**cfg.values, "sweep": {"windows.length_s": [0.5, 1.5]}})
    res = evaluate_config(cfg, out_dir=tmp_path / "run", progress=False)
    run = tmp_path / "run"
    for f in (
        "config.resolved.json",
        "metrics.json",
        "report.md",
        "confusion.png",
        "sweep.png",
        "sweep.csv",
        "folds.csv",
        "per_class.csv",
        "confusion_before.csv",
        "confusion_after.csv",
        "point-00/predictions.csv",
        "point-01/confusion.png",
    ):
        assert (run / f).is_file(), f
    assert [r["windows.length_s"] for r in res["sweep"]] == [0.5, 1.5]
    m = json.loads((run / "metrics.json").read_text())
    assert m["accuracy"] == res["accuracy"] and "per_class" in m
    assert not list(tmp_path.glob(".run.*"))  # no temporary folder left behind


def test_folder_source_meta_label(tmp_path):
    write_synth_folder(tmp_path / "data", n_subjects=3, seconds_per_mode=6.0)
    cfg = parse_config(
        {"name": "pos", "data": {"source": "folder", "path": "data", "label": "position", "group": "user"}}, base_dir=tmp_path
    )
    res = evaluate_config(cfg, write=False, progress=False)
    assert res["labels"] == ["InHand", "Pocket"] and res["n_groups"] == 3


def test_simulated_position_label(tmp_path):
    """data.label = 'position' on simulated data: every window carries its recording's meta position."""
    sim = {"subjects": 3, "duration_s": 20.0, "modes": ["walk", "run"], "positions": ["front-pocket", "hand-flat", "bag"]}
    cfg = parse_config({"name": "simpos", "data": {"source": "simulated", "label": "position", "simulated": sim}})
    res = evaluate_config(cfg, out_dir=tmp_path / "run", progress=False)
    assert res["labels"] == ["front-pocket", "hand-flat", "bag"] and res["n_recordings"] == 9 and len(res["folds"]) == 3
    pred = pd.read_csv(tmp_path / "run" / "predictions.csv")
    # the window's label is the position in its recording's name (S01-R1-front-pocket)
    assert (pred["label"] == pred["recording"].str.split("-", n=2).str[2]).all()
    assert set(pred["label"]) == set(sim["positions"]) and res["accuracy_before_correction"] > 1 / 3


@pytest.mark.slow
def test_parallel_folds_equal_serial(tmp_path):
    a = evaluate_config(_tiny_cfg("linear-ovo-svm"), write=False, progress=False)
    b = evaluate_config(_tiny_cfg("linear-ovo-svm", cv={"n_jobs": 2}), write=False, progress=False)
    assert a["folds"] == [dict(f, fit_s=a["folds"][i]["fit_s"]) for i, f in enumerate(b["folds"])]


def _write_cfg(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "c.toml"
    p.write_text(text)
    return p


CLI_CFG = """
name = "cli"
[data]
source = "simulated"
[data.simulated]
subjects = 2
duration_s = 40.0
modes = ["walk", "run"]
[train]
model_dir = "model"
"""


def test_cli_evaluate_train_predict_json(tmp_path, capsys):
    cfg = _write_cfg(tmp_path, CLI_CFG)
    assert main(["evaluate", str(cfg), "--out", str(tmp_path / "run"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for k in ("accuracy", "macro_f1", "per_class", "folds", "accuracy_before_correction", "accuracy_after_correction", "run_dir"):
        assert k in out
    assert main(["train", str(cfg)]) == 0
    assert (tmp_path / "model" / "model.json").is_file()
    capsys.readouterr()
    from gaitml.io import write_gaitml_csv
    from gaitml.simulate import simulate_dataset

    rec = simulate_dataset(n_subjects=1, duration_s=20.0, modes=("walk", "run"), seed=5, sampling_rate_hz=100.0)[0]
    write_gaitml_csv(rec, tmp_path / "in.csv")
    assert main(["predict", str(tmp_path / "model"), str(tmp_path / "in.csv"), "--json", "--out", str(tmp_path / "pred.csv")]) == 0
    cap = capsys.readouterr()
    js = json.loads(cap.out)
    assert set(js["windows"][0]) == {
        "t_start_s",
        "t_end_s",
        "mode",
        "in_domain",
        "out_of_domain_reason",
        "side_direction_unsure",
        "run_at_walking_cadence",
        "still_vetoed",
        "still_unsure",
    }
    assert all((w["out_of_domain_reason"] is None) == w["in_domain"] for w in js["windows"])  # a reason for every flagged window
    assert all(isinstance(w["in_domain"], bool) for w in js["windows"]) and 0.0 <= js["out_of_domain_fraction"] <= 1.0
    assert sum(js["counts"].values()) == len(js["windows"])
    assert "resampled the input from 100 Hz" in cap.err
    assert (tmp_path / "pred.csv").is_file()
    assert main(["predict", str(tmp_path / "model"), str(tmp_path / "in.csv"), "--json", "--no-correction"]) == 0
    raw = json.loads(capsys.readouterr().out)
    assert raw["correction"] is False and len(raw["windows"]) == len(js["windows"])


def test_cli_errors_exit_2_with_one_line(tmp_path, capsys):
    bad = _write_cfg(tmp_path, 'name = "x"\n[windows]\nlength_s = "long"\n')
    assert main(["evaluate", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "windows.length_s" in err
    assert main(["predict", str(tmp_path / "no-model"), str(bad)]) == 2
    assert "model folder not found" in capsys.readouterr().err
    sweep = _write_cfg(tmp_path, 'name = "x"\n[sweep]\n"windows.length_s" = [1.0, 2.0]\n')
    assert main(["train", str(sweep)]) == 2
    assert "[sweep]" in capsys.readouterr().err


def test_correction_never_lowers_on_isolated_errors():
    from gaitml.evaluation.classification import classification_metrics, correct_by_recording

    y = np.array(["walk"] * 10 + ["run"] * 10)
    pred = y.copy()
    pred[[3, 14]] = ["run", "walk"]
    rec = np.array([0] * 20)
    fixed = correct_by_recording(pred, rec, np.arange(20.0))
    assert classification_metrics(y, fixed)["accuracy"] == 1.0
    # two recordings are never corrected across their boundary
    rec2 = np.array([0] * 10 + [1] * 10)
    pred2 = np.array(["walk"] * 9 + ["run"] + ["walk"] + ["run"] * 9)
    out = correct_by_recording(pred2, rec2, np.r_[np.arange(10.0), np.arange(10.0)])
    assert out[9] == "run" and out[10] == "walk"
