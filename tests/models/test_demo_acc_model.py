"""The shipped accelerometer-only demo model ``models/demo-acc`` (issue 12).

It is ``experiments/demo-acc.toml`` (``experiments/demo.toml`` with ``features.set =
"all52"``) trained by ``gaitml train experiments/demo-acc.toml --out models/demo-acc``.
The fast tests check that the shipped folder was trained from the committed config and
still predicts what it predicted when it was shipped; the slow test retrains it and
compares it with the shipped one: the same model up to floating-point rounding (another
CPU's vector width changes the last bit of a mean, and liblinear then stops one iteration
earlier or later inside its tolerance), and the same modes and flags window for window.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from gaitml.io import read_recording, write_gaitml_csv
from gaitml.models import load_model, predict_recording
from gaitml.pipeline.config import load_config
from gaitml.recording import Recording
from tests.conftest import ROOT

DEMO_ACC = ROOT / "models" / "demo-acc"
CONFIG = ROOT / "experiments" / "demo-acc.toml"
SAMPLE = ROOT / "data" / "samples" / "S02-mixed.csv"


def _flat(d: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out.update(_flat(v, f"{prefix}{k}."))
        else:
            out[prefix + k] = v
    return out


def _acc_only(rec: Recording) -> Recording:
    return Recording.from_arrays(rec.acc, rec.sampling_rate_hz, labels=rec.labels)


def test_shipped_demo_acc_was_trained_from_its_config():
    model = load_model(DEMO_ACC)
    cfg = load_config(CONFIG)
    assert model.info["training_config"] == json.loads(json.dumps(cfg.resolved()))
    assert model.info["name"] == "demo-acc" and model.feature_set == "all52" and model.frame == "phone"
    assert not [n for n in model.feature_names if n.startswith("gyr")]
    assert model.info["training_data"]["n_windows"] == 12576  # the demo's windows (the same 32 subjects, seed 1000)
    assert model.domain is not None and model.domain.gravity_check
    assert model.domain.positions == {"hand-flat": 9432, "hand-tilted": 3144}
    assert (DEMO_ACC / "MODEL.md").read_text().startswith("# Model card: demo-acc")
    assert sum(p.stat().st_size for p in DEMO_ACC.iterdir()) < 200_000


def test_demo_acc_config_is_the_demo_config_without_the_gyroscope():
    acc = _flat(load_config(CONFIG).resolved())
    demo = _flat(load_config(ROOT / "experiments" / "demo.toml").resolved())
    differ = {k for k in acc.keys() | demo.keys() if acc.get(k) != demo.get(k)}
    assert differ == {"name", "description", "features.set", "train.model_dir"}
    assert (acc["features.set"], demo["features.set"]) == ("all52", "all52+gyro")


def test_demo_acc_reads_an_accelerometer_only_recording_as_when_it_was_shipped():
    """Pinned: the window modes of the committed sample (checked when the model was shipped), gyroscope or not."""
    model = load_model(DEMO_ACC)
    rec = read_recording(SAMPLE)
    with_gyro = predict_recording(model, rec)
    t = predict_recording(model, _acc_only(rec))
    np.testing.assert_array_equal(t["mode_raw"].to_numpy(), with_gyro["mode_raw"].to_numpy())
    assert t["mode"].value_counts().to_dict() == {"backward": 18, "side_left": 17, "run": 15, "walk": 14, "side_right": 13}
    assert bool(t["in_domain"].astype(bool).all())
    sel = t["label_fraction"].to_numpy() >= 0.5
    # the sample's walker is a calm one (hand gain 0.30): without the gyroscope 71 % of its windows
    # are right (models/demo with the gyroscope: 92 %; both models before the hand gain: 38-40 %)
    assert np.mean(t["mode"].to_numpy()[sel] == t["label"].to_numpy()[sel]) > 0.68


def test_gaitml_predict_with_demo_acc_on_an_accelerometer_only_file(tmp_path, capsys):
    from gaitml.cli import main

    path = tmp_path / "acc_only.csv"
    write_gaitml_csv(_acc_only(read_recording(SAMPLE)), path)
    assert main(["predict", str(DEMO_ACC), str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["out_of_domain_fraction"] == 0.0
    assert {w["in_domain"] for w in out["windows"]} == {True}


@pytest.mark.slow
def test_retraining_demo_acc_gives_the_shipped_model(tmp_path):
    """``gaitml train experiments/demo-acc.toml`` again (about 40 s): the shipped model up to rounding.

    Preprocessing and domain arrays agree to 1e-9 (relative to the array's largest entry); the SVM weights to 2 % of the
    largest weight (liblinear's stopping tolerance: on one machine a pair's solver took one
    iteration more, which moved a weight by 0.026 of a largest 3.16); and what a user sees,
    the mode and the flag of every window, is the same.
    """
    from gaitml.cli import main
    from gaitml.simulate import simulate_dataset

    assert main(["train", str(CONFIG), "--out", str(tmp_path / "demo-acc")]) == 0
    shipped = np.load(DEMO_ACC / "arrays.npz", allow_pickle=False)
    again = np.load(tmp_path / "demo-acc" / "arrays.npz", allow_pickle=False)
    # the shipped model still carries the domain's feature quantiles, no longer written nor read (issue 26)
    retired = {"domain__feature_lo", "domain__feature_hi"}
    assert sorted(set(shipped.files) - retired) == sorted(again.files)
    for name in again.files:
        a, b = shipped[name], again[name]
        assert a.shape == b.shape and a.dtype == b.dtype, name
        if name == "n_iter_":  # the solver's iteration counts are what rounding may change
            np.testing.assert_allclose(b, a, atol=2, err_msg=name)
        elif a.dtype.kind != "f":
            np.testing.assert_array_equal(b, a, err_msg=name)
        elif name in ("coef_", "intercept_"):
            np.testing.assert_allclose(b, a, rtol=0, atol=0.02 * np.abs(shipped["coef_"]).max(), err_msg=name)
        else:
            np.testing.assert_allclose(b, a, rtol=1e-9, atol=1e-9 * np.abs(a).max(), err_msg=name)
    a = json.loads((DEMO_ACC / "model.json").read_text())
    b = json.loads((tmp_path / "demo-acc" / "model.json").read_text())
    for key in ("training_config", "training_data", "estimator", "feature_names", "labels", "window"):
        assert a[key] == b[key], key
    for key in ("distance_threshold", "distance_threshold_in_sample", "gravity_threshold_rad", "gravity_threshold_in_sample_rad"):
        assert b["domain"][key] == pytest.approx(a["domain"][key], rel=1e-9), key
    assert b["cv_scores"]["accuracy_before"] == pytest.approx(a["cv_scores"]["accuracy_before"], abs=2e-3)
    shipped_model, retrained = load_model(DEMO_ACC), load_model(tmp_path / "demo-acc")
    for rec in [read_recording(SAMPLE), *simulate_dataset(n_subjects=2, duration_s=120.0, pose="mixed", seed=2024)]:
        ta, tb = predict_recording(shipped_model, rec), predict_recording(retrained, rec)
        np.testing.assert_array_equal(tb["mode"].to_numpy(), ta["mode"].to_numpy())
        np.testing.assert_array_equal(tb["in_domain"].to_numpy(), ta["in_domain"].to_numpy())


@pytest.mark.realdata
def test_demo_acc_meets_the_issue_targets_on_real_hand_held_walking():
    """Oxford InHand (16 walks, 3 users): walk >= 90 % of the windows, silently wrong (neither walk
    nor flagged) <= 5 %; measured 98.9 % and 0.8 % (90.5 % and 5.5 % before the simulator's hand
    gain; held out per user: 95.6 % and 2.4 %, experiments/reports/model-domain.md)."""
    from experiments.scripts.domain_report import _add, score
    from gaitml.io import read_dataset
    from tests.conftest import shared

    recs = [r for r in read_dataset(shared("oxford-step-counter", "optimisation")) if r.meta.get("position") == "InHand"]
    assert len(recs) == 16
    model = load_model(DEMO_ACC)
    tot: dict = {}
    for r in recs:
        tot = _add(tot, score(model, r))
    assert tot["walk_all"] / tot["windows"] >= 0.90
    assert tot["silent"] / tot["windows"] <= 0.05
