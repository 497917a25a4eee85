"""The shipped accelerometer-only demo model ``models/demo-acc``.

It is ``experiments/demo-acc.toml`` (32 simulated subjects holding the phone flat or tilted,
``features.set = "all52"``; the hand-held model ``experiments/demo.toml`` was before it was
trained on real carried phones) trained by ``gaitml train experiments/demo-acc.toml --out models/demo-acc``.
The fast tests check that the shipped folder was trained from the committed config and
reads accelerometer-only recordings; the slow test retrains it and compares what a user
sees (every window's mode and flag, the CV accuracy) and the arrays, to tolerances that
follow from the solver's recorded distance to the optimum (gaitml.models._svm), so a
retrain on another CPU or with another BLAS thread count passes.
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


def _as_trained(trained: dict, committed: dict) -> dict:
    """``committed`` (a resolved config) without the settings added to the schema after ``trained`` was recorded, at their default (off)."""
    out = json.loads(json.dumps(committed))
    if "acc_range_ms2" not in trained["features"] and out["features"].get("acc_range_ms2") == 0:
        out["features"].pop("acc_range_ms2")
    return out


def _acc_only(rec: Recording) -> Recording:
    return Recording.from_arrays(rec.acc, rec.sampling_rate_hz, labels=rec.labels)


def test_shipped_demo_acc_was_trained_from_its_config():
    model = load_model(DEMO_ACC)
    cfg = load_config(CONFIG)
    assert model.info["training_config"] == _as_trained(model.info["training_config"], cfg.resolved())
    assert model.info["name"] == "demo-acc" and model.feature_set == "all52" and model.frame == "phone"
    assert not [n for n in model.feature_names if n.startswith("gyr")]
    # the demo's windows (the same 32 subjects, seed 1000), each recording once more per data.augment.rates copy
    assert model.info["training_data"]["n_windows"] == 12576 * (1 + len(cfg["data"]["augment"]["rates"]))
    assert model.domain is not None and model.domain.gravity_check
    assert model.domain.positions == {"hand-flat": 9432, "hand-tilted": 3144}
    assert (DEMO_ACC / "MODEL.md").read_text().startswith("# Model card: demo-acc")
    assert sum(p.stat().st_size for p in DEMO_ACC.iterdir()) < 200_000


def test_demo_acc_config_is_the_hand_held_simulator_config():
    """The accelerometer twin stays the simulator's hand-held phone (the tyrex recipe read real pockets as run)."""
    acc = _flat(load_config(CONFIG).resolved())
    assert acc["data.source"] == "simulated" and acc["data.simulated.pose"] == "mixed"
    assert acc["data.simulated.subjects"] == 32 and acc["features.set"] == "all52"


def test_demo_acc_reads_an_accelerometer_only_recording_like_one_with_the_gyroscope():
    """Without the gyroscope columns the sample's windows get the same modes, all in domain, most of them right."""
    model = load_model(DEMO_ACC)
    rec = read_recording(SAMPLE)
    with_gyro = predict_recording(model, rec)
    t = predict_recording(model, _acc_only(rec))
    np.testing.assert_array_equal(t["mode_raw"].to_numpy(), with_gyro["mode_raw"].to_numpy())
    assert bool(t["in_domain"].astype(bool).all())
    sel = t["label_fraction"].to_numpy() >= 0.5
    # the sample's walker is a calm one (hand gain 0.30): without the gyroscope 66 % of its windows
    # are right with the 20 Hz training copies, 71 % without them (models/demo with the gyroscope: 92 %;
    # both models before the hand gain: 38-40 %)
    assert np.mean(t["mode"].to_numpy()[sel] == t["label"].to_numpy()[sel]) > 0.63


def test_gaitml_predict_with_demo_acc_on_an_accelerometer_only_file(tmp_path, capsys):
    from gaitml.cli import main

    path = tmp_path / "acc_only.csv"
    write_gaitml_csv(_acc_only(read_recording(SAMPLE)), path)
    assert main(["predict", str(DEMO_ACC), str(path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["out_of_domain_fraction"] == 0.0
    assert {w["in_domain"] for w in out["windows"]} == {True}


#: CV accuracy of a retrain vs the shipped record: 6 of the 12,576 held-out windows (the weights agree to about
#: 1e-5, so only a window within about that of a decision boundary can change class).
CV_ACCURACY_TOLERANCE = 6 / 12576


def _standardised(coef: np.ndarray, intercept: np.ndarray, mean: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """Pairwise (weights, bias) in the standardised space the solver works in (undoing the fold into raw units)."""
    return np.c_[coef * scale, intercept + coef @ mean]


@pytest.mark.slow
def test_retraining_demo_acc_gives_the_shipped_model(tmp_path):
    """``gaitml train experiments/demo-acc.toml`` again (about 40 s) gives the shipped model.

    What a user sees is the same: the mode and the flag of every window of the sample and two
    simulated walkers, and the CV accuracy within :data:`CV_ACCURACY_TOLERANCE`. The solver
    converged on both (``n_iter_`` below ``max_iter``), and every pair's standardised weights
    and bias differ by at most the sum of the two fits' final gradient norms (each fit is
    within its own of the exact optimum: the objective is 1-strongly convex), with a factor 2
    for the optimum itself moving with the last bits of the inputs. Preprocessing and domain
    arrays are sums and products, not iterations: they agree to 1e-9 of their largest entry.
    """
    from gaitml.cli import main
    from gaitml.simulate import simulate_dataset

    assert main(["train", str(CONFIG), "--out", str(tmp_path / "demo-acc")]) == 0
    shipped = np.load(DEMO_ACC / "arrays.npz", allow_pickle=False)
    again = np.load(tmp_path / "demo-acc" / "arrays.npz", allow_pickle=False)
    # a model trained before the domain record stopped writing its feature quantiles still carries them; nothing reads them
    retired = {"domain__feature_lo", "domain__feature_hi"}
    assert sorted(set(shipped.files) - retired) == sorted(set(again.files) - retired)
    a_info = json.loads((DEMO_ACC / "model.json").read_text())
    b_info = json.loads((tmp_path / "demo-acc" / "model.json").read_text())
    max_iter = a_info["estimator"]["params"]["max_iter"]
    for arrays in (shipped, again):
        assert np.all(arrays["n_iter_"] < max_iter)
        assert np.all(np.isfinite(arrays["gradient_norm_"]))
    assert a_info["estimator"]["state"]["converged_"] and b_info["estimator"]["state"]["converged_"]
    bound = 2 * (shipped["gradient_norm_"] + again["gradient_norm_"])
    moved = np.linalg.norm(
        _standardised(again["coef_"], again["intercept_"], again["mean_"], again["scale_"])
        - _standardised(shipped["coef_"], shipped["intercept_"], shipped["mean_"], shipped["scale_"]),
        axis=1,
    )
    assert np.all(moved <= bound), (moved, bound)
    iterative = {"coef_", "intercept_", "n_iter_", "gradient_norm_"}  # checked above, through the bound
    for name in sorted(set(again.files) - iterative - retired):
        a, b = shipped[name], again[name]
        assert a.shape == b.shape and a.dtype == b.dtype, name
        if a.dtype.kind != "f":
            np.testing.assert_array_equal(b, a, err_msg=name)
        else:
            np.testing.assert_allclose(b, a, rtol=1e-9, atol=1e-9 * np.abs(a).max(), err_msg=name)
    b_info["training_config"] = _as_trained(a_info["training_config"], b_info["training_config"])
    for key in ("training_config", "training_data", "feature_names", "labels", "window"):
        assert a_info[key] == b_info[key], key
    assert a_info["estimator"]["params"] == b_info["estimator"]["params"]
    for key in ("distance_threshold", "distance_threshold_in_sample", "gravity_threshold_rad", "gravity_threshold_in_sample_rad"):
        assert b_info["domain"][key] == pytest.approx(a_info["domain"][key], rel=1e-9), key
    for key in ("accuracy_before", "accuracy_after"):
        assert b_info["cv_scores"][key] == pytest.approx(a_info["cv_scores"][key], abs=CV_ACCURACY_TOLERANCE), key
    shipped_model, retrained = load_model(DEMO_ACC), load_model(tmp_path / "demo-acc")
    for rec in [read_recording(SAMPLE), *simulate_dataset(n_subjects=2, duration_s=120.0, pose="mixed", seed=2024)]:
        ta, tb = predict_recording(shipped_model, rec), predict_recording(retrained, rec)
        np.testing.assert_array_equal(tb["mode"].to_numpy(), ta["mode"].to_numpy())
        np.testing.assert_array_equal(tb["in_domain"].to_numpy(), ta["in_domain"].to_numpy())
