"""train + predict + pdr with a step-window model through the CLI; model.json keeps by/detector; old models read as time."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gaitml.cli import main
from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.io import write_gaitml_csv
from gaitml.models import load_model, predict_step_windows
from gaitml.simulate import simulate_dataset
from gaitml.steps import get_detector
from tests.conftest import ROOT
from tests.stepwin.conftest import STEP_MODEL_CONFIG as CONFIG


@pytest.fixture(scope="module")
def trained(step_model_dir):
    d = step_model_dir
    rec = simulate_dataset(n_subjects=1, duration_s=40.0, seed=321, segment_s=(6.0, 9.0))[0]
    write_gaitml_csv(rec, d / "walk.csv")
    return d, rec


def test_model_json_stores_the_window_kind_and_detector(trained):
    d, _ = trained
    info = json.loads((d / "model" / "model.json").read_text())
    assert info["window"]["by"] == "steps" and info["window"]["detector"] == "ifsm"
    assert info["cv_scores"]["accuracy_after"] > 0.6  # three simulated walkers: far above chance (0.2)
    m = load_model(d / "model")
    assert m.window_by == "steps" and m.window_detector == "ifsm"
    assert "one per detected step" in (d / "model" / "MODEL.md").read_text()


def test_old_models_read_as_time_windows():
    m = load_model(ROOT / "models" / "demo")
    assert "by" not in m.info["window"]
    assert m.window_by == "time" and m.window_detector == ""


def test_predict_gives_one_row_per_detected_step(trained, capsys):
    d, rec = trained
    capsys.readouterr()
    assert main(["predict", str(d / "model"), str(d / "walk.csv"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    n_steps = len(get_detector("ifsm").detect(rec).steps_)
    assert out["window_by"] == "steps" and out["detector"] == "ifsm"
    assert len(out["windows"]) == n_steps
    t = [w["t_event_s"] for w in out["windows"]]
    assert t == sorted(t)
    assert sum(out["counts"].values()) == n_steps
    # per-step modes agree with the true labels on most steps of a new walker
    table = predict_step_windows(load_model(d / "model"), rec)
    assert np.mean(table["mode"].to_numpy() == table["label"].to_numpy()) > 0.6


def test_predict_out_csv_has_step_columns(trained, tmp_path, capsys):
    d, _ = trained
    assert main(["predict", str(d / "model"), str(d / "walk.csv"), "--out", str(tmp_path / "p.csv")]) == 0
    header = (tmp_path / "p.csv").read_text().splitlines()[0].split(",")
    assert header[:8] == ["step", "start", "end", "t_start_s", "t_end_s", "t_event_s", "mode_raw", "mode"]


def test_pdr_uses_the_per_step_predictions_directly(trained, capsys):
    d, rec = trained
    capsys.readouterr()
    assert main(["pdr", str(d / "walk.csv"), "--model", str(d / "model"), "--json"]) == 0
    out, err = capsys.readouterr()
    res = json.loads(out)
    assert "no window lookup" in err and "step-window model's detector ifsm" in err
    modes = [p["mode"] for p in res["trajectory"][1:]]
    table = predict_step_windows(load_model(d / "model"), rec)
    assert res["n_steps"] == len(table)
    # the PDR step modes are the model's per-step predictions, except steps outside the model's
    # training domain, which move forward ('walk') and are counted
    flags = table["in_domain"].tolist()
    assert all(f in (True, False) for f in flags)
    assert modes == [m if f else "walk" for m, f in zip(table["mode"], flags, strict=True)]
    assert res["out_of_domain_steps"] == flags.count(False)
    assert flags.count(False) < 0.2 * len(flags)  # a walk like the training data is mostly in domain


def test_predict_with_a_step_model_flags_every_step(trained, capsys):
    d, rec = trained
    capsys.readouterr()
    assert main(["predict", str(d / "model"), str(d / "walk.csv"), "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    flags = [w["in_domain"] for w in res["windows"]]
    assert flags and all(f in (True, False) for f in flags)
    assert res["out_of_domain_fraction"] == pytest.approx(flags.count(False) / len(flags))


def test_pdr_with_another_detector_classifies_that_detectors_steps(trained, capsys):
    d, rec = trained
    capsys.readouterr()
    assert main(["pdr", str(d / "walk.csv"), "--model", str(d / "model"), "--detector", "single-peak", "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["n_steps"] == len(get_detector("single-peak").detect(rec).steps_)


def test_evaluate_with_step_windows(tmp_path, capsys):
    (tmp_path / "cfg.toml").write_text(CONFIG.replace("subjects = 3", "subjects = 2").replace("duration_s = 60.0", "duration_s = 30.0"))
    capsys.readouterr()
    assert main(["evaluate", str(tmp_path / "cfg.toml"), "--out", str(tmp_path / "run"), "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert len(res["folds"]) == 2 and res["n_windows"] > 50
    assert res["n_windows"] == res["n_windows_total"] - res["n_dropped_label_fraction"]


def test_json_export_describes_step_windows(trained, tmp_path):
    d, _ = trained
    assert main(["model", "export", str(d / "model"), "--format", "json", "--out", str(tmp_path / "m.json")]) == 0
    win = json.loads((tmp_path / "m.json").read_text())["window"]
    assert win["by"] == "steps" and win["detector"] == "ifsm" and "one window per detected step" in win["rule"]


def test_raw_input_model_on_step_windows(tmp_path):
    """cnn1d reads each step resampled to a fixed length (32 samples)."""
    pytest.importorskip("torch")
    from gaitml.pipeline import parse_config, train_config

    cfg = parse_config(
        {
            "name": "cnn-steps",
            "data": {"simulated": {"subjects": 2, "duration_s": 30.0}},
            "windows": {"by": "steps"},
            "model": {"kind": "cnn1d", "params": {"epochs": 1, "channels": [4, 4], "batch_size": 64}},
            "train": {"cross_validate": False},
        }
    )
    model = train_config(cfg, out_dir=tmp_path / "m", progress=False)
    assert model.info["window"]["raw_length_samples"] == 32
    rec = simulate_dataset(n_subjects=1, duration_s=20.0, seed=9)[0]
    table = predict_step_windows(load_model(tmp_path / "m"), rec)
    assert len(table) == len(get_detector("single-peak").detect(rec).steps_)
    assert set(table["mode"]) <= set(model.labels)


def test_stride_window_model_predicts_per_stride_and_pdr_gives_each_step_its_strides_mode(tmp_path, capsys):
    from gaitml.features import make_step_windows
    from gaitml.pipeline import parse_config, train_config

    cfg = parse_config(
        {
            "name": "strides",
            "data": {"simulated": {"subjects": 2, "duration_s": 40.0}},
            "windows": {"by": "strides", "detector": "magnitude-std"},
            "train": {"cross_validate": False},
        }
    )
    model = train_config(cfg, out_dir=tmp_path / "m", progress=False)
    assert model.info["window"]["by"] == "strides" and model.info["window"]["detector"] == "magnitude-std"
    rec = simulate_dataset(n_subjects=1, duration_s=30.0, seed=8, segment_s=(6.0, 9.0))[0]
    write_gaitml_csv(rec, tmp_path / "walk.csv")
    table = predict_step_windows(load_model(tmp_path / "m"), rec)
    assert len(table) == len(make_step_windows(rec, "strides", "magnitude-std", min_label_fraction=0.0)) > 10
    capsys.readouterr()
    assert main(["pdr", str(tmp_path / "walk.csv"), "--model", str(tmp_path / "m"), "--json"]) == 0
    out, err = capsys.readouterr()
    res = json.loads(out)
    # a stride-window model brings no step detector: the PDR's steps come from the default one
    assert "stride-window model" in err and res["n_steps"] == len(get_detector(DEFAULT_STEP_DETECTOR).detect(rec).steps_)
    assert {p["mode"] for p in res["trajectory"][1:]} <= set(table["mode"])


def test_step_windows_check_the_dynamics_of_every_second_step_in_time_order(trained):
    """The dynamics part of a step model: descriptors of the computed steps (in time order) only, whatever the row order."""
    from gaitml.features.step_windows import extract_step_features, make_step_windows
    from gaitml.models._dataset import resample_recording
    from gaitml.models._step_windows import step_domain_columns
    from gaitml.models.domain import orientation_dynamics, span_gravity

    d, rec = trained
    model = load_model(d / "model")
    dom = model.domain
    assert dom.dynamics is not None and dom.dynamics_every == 2
    r = resample_recording(rec, model.sampling_rate_hz)
    w = make_step_windows(r, "steps", "ifsm", min_label_fraction=0.0)
    assert len(w) > 20 and (np.diff(w["start"].to_numpy()) > 0).all()
    s, e = w["start"].to_numpy(np.int64), w["end"].to_numpy(np.int64)
    X = extract_step_features(r, w, subset=dom.feature_set).to_numpy(dtype=float)
    # plainly: every step's descriptors, the check reads those of steps 0, 2, 4, ...
    ref = dom.check(X, span_gravity(r.acc, s, e), orientation_dynamics(r.acc, r.gyr, s, e, r.sampling_rate_hz))
    got = step_domain_columns(model, r, w)
    np.testing.assert_array_equal(got["in_domain"].astype(bool), ref["in_domain"])
    np.testing.assert_allclose(got["dynamics_distance"], ref["dynamics_distance"], rtol=1e-12)
    shuffled = np.random.default_rng(0).permutation(len(w))  # rows in another order: the same per-step answer
    back = step_domain_columns(model, r, w.iloc[shuffled].reset_index(drop=True))
    np.testing.assert_array_equal(back["in_domain"].astype(bool), ref["in_domain"][shuffled])
    np.testing.assert_allclose(back["dynamics_distance"], ref["dynamics_distance"][shuffled], rtol=1e-12)
