"""Model kinds, the OVO vote, determinism, artifacts (tamper tests) and predict_recording."""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest

from gaitml.errors import ConfigError, InputError, ModelError
from gaitml.models import (
    LinearOVOSVM,
    build_window_dataset,
    load_model,
    make_model,
    model_param_names,
    ovo_vote,
    predict_recording,
    save_model,
    torch_available,
)
from gaitml.models._svm import PRIMAL_TOL, primal_gradient_norm
from tests.models.synth import synth_set

needs_torch = pytest.mark.skipif(not torch_available(), reason="torch extra not installed")


@pytest.fixture(scope="module")
def dataset():
    recs = synth_set(3, seconds_per_mode=12.0)
    return build_window_dataset(recs, groups=[r.meta["subject"] for r in recs], length_s=1.5, overlap=0.5, need_raw=True)


def test_ovo_vote_majority_and_tie_break():
    pairs = np.array([[0, 1], [0, 2], [1, 2]])
    # class 0 beats 1 and 2 -> 0
    assert ovo_vote(np.array([[1.0, 1.0, -1.0]]), pairs, 3)[0] == 0
    # cycle 0>1, 2>0, 1>2: one vote each; confidences decide (class 2 wins by most margin)
    d = np.array([[0.1, -2.0, 0.1]])
    assert ovo_vote(d, pairs, 3)[0] == 2


def test_linear_ovo_svm_matches_sklearn_one_vs_one(dataset):
    from sklearn.multiclass import OneVsOneClassifier
    from sklearn.svm import LinearSVC

    X, y = dataset.inputs("features"), dataset.y
    ours = LinearOVOSVM(C=0.5).fit(X, y)
    Z = (X - ours.mean_) / ours.scale_
    ref = OneVsOneClassifier(LinearSVC(C=0.5, dual=False, tol=PRIMAL_TOL, max_iter=2000, random_state=0)).fit(Z, y)
    # same pairwise machines and the same vote: the predictions agree
    assert np.array_equal(ours.predict(X), ref.predict(Z))
    assert ours.converged_
    assert ours.coef_.shape == (3, X.shape[1])


def test_linear_ovo_svm_pairwise_weights_equal_liblinear(dataset):
    from sklearn.svm import LinearSVC

    X, y = dataset.inputs("features"), dataset.y
    m = LinearOVOSVM().fit(X, y)
    Z = (X - m.mean_) / m.scale_
    i, j = m.pairs_[0]
    mask = np.isin(y, [m.classes_[i], m.classes_[j]])
    clf = LinearSVC(dual=False, tol=PRIMAL_TOL, random_state=0).fit(Z[mask], np.where(y[mask] == m.classes_[i], 1, -1))
    np.testing.assert_allclose(X[mask] @ m.coef_[0] + m.intercept_[0], clf.decision_function(Z[mask]), rtol=1e-9, atol=1e-9)


def _primal_objective(Z, y, w, b, C):
    margin = np.maximum(0.0, 1.0 - y * (Z @ w + b))
    return 0.5 * (w @ w + b * b) + C * np.sum(margin**2)


def test_primal_gradient_norm_is_the_norm_of_the_objectives_gradient():
    rng = np.random.default_rng(3)
    Z = rng.standard_normal((200, 4))
    y = np.where(Z[:, 0] + 0.5 * rng.standard_normal(200) > 0, 1.0, -1.0)
    w, b, C, h = rng.standard_normal(4) * 0.3, 0.2, 0.7, 1e-6
    theta = np.r_[w, b]
    fd = [
        (_primal_objective(Z, y, *np.split(theta + h * e, [4]), C) - _primal_objective(Z, y, *np.split(theta - h * e, [4]), C)) / (2 * h)
        for e in np.eye(5)
    ]
    fd = np.asarray(fd, dtype=float)
    assert primal_gradient_norm(Z, y, w, b, C) == pytest.approx(np.linalg.norm(fd), rel=1e-5)


def test_linear_ovo_svm_converges_and_records_its_distance_to_the_optimum(dataset):
    """Every pair stops on its tolerance, and a last-bit change of the input (another CPU's sums) moves the
    standardised weights by no more than the two fits' recorded gradient norms (the objective is 1-strongly convex)."""
    X, y = dataset.inputs("features"), dataset.y
    a = LinearOVOSVM().fit(X, y)
    noise = np.random.default_rng(0).standard_normal(X.shape)
    b = LinearOVOSVM().fit(X * (1 + 4e-16 * noise), y)
    for m in (a, b):
        assert m.converged_ and np.all(m.n_iter_ < m.max_iter)
        assert np.all(np.isfinite(m.gradient_norm_)) and np.all(m.gradient_norm_ < 1e-3)

    def standardised(m):
        return np.c_[m.coef_ * m.scale_, m.intercept_ + m.coef_ @ m.mean_]

    moved = np.linalg.norm(standardised(a) - standardised(b), axis=1)
    assert np.all(moved <= a.gradient_norm_ + b.gradient_norm_ + 1e-9)
    loose = LinearOVOSVM(tol=1e-4).fit(X, y)  # scikit-learn's default: much further from the optimum
    assert loose.gradient_norm_.max() > 100 * a.gradient_norm_.max()


def test_linear_ovo_svm_dual_solver_keeps_its_own_tolerance(dataset):
    m = LinearOVOSVM(loss="hinge", max_iter=5000).fit(dataset.inputs("features"), dataset.y)
    assert m._tol() == 1e-4 and np.isnan(m.gradient_norm_).all()


@pytest.mark.parametrize("bad", [{"C": 0}, {"C": -1.0}, {"solver": "sgd"}, {"loss": "log"}, {"tol": 0.0}, {"tol": "tight"}])
def test_svm_bad_params(dataset, bad):
    with pytest.raises(InputError, match=next(iter(bad))):
        LinearOVOSVM(**bad).fit(dataset.inputs("features"), dataset.y)


def test_svm_refuses_wrong_width_and_one_class(dataset):
    m = LinearOVOSVM().fit(dataset.inputs("features"), dataset.y)
    with pytest.raises(InputError, match="34 features, but LinearOVOSVM is expecting 52 features"):
        m.predict(np.zeros((2, 34)))
    with pytest.raises(InputError, match="at least 2 classes") as exc:
        LinearOVOSVM().fit(np.zeros((5, 3)) + np.arange(5)[:, None], ["a"] * 5)
    assert "got 1 class (a);" in str(exc.value) and "np.str_" not in str(exc.value)


def test_make_model_errors():
    with pytest.raises(ConfigError, match="allowed: linear-ovo-svm, mlp, cnn1d"):
        make_model("rbf-svm")
    with pytest.raises(ConfigError, match=r"model.params.gamma .*allowed: C"):
        make_model("linear-ovo-svm", {"gamma": 1})
    assert "C" in model_param_names("linear-ovo-svm")


def test_torch_missing_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "torch", None)  # import torch -> ImportError
    with pytest.raises(ModelError, match=r"pip install 'gaitml\[torch\]'"):
        make_model("mlp")
    with pytest.raises(ModelError, match="torch"):
        make_model("cnn1d")


@pytest.mark.parametrize("kind", ["linear-ovo-svm", pytest.param("mlp", marks=needs_torch), pytest.param("cnn1d", marks=needs_torch)])
def test_each_kind_is_deterministic(dataset, kind):
    params = {} if kind == "linear-ovo-svm" else {"epochs": 3}
    X = dataset.inputs(make_model(kind).input_kind)
    p1 = make_model(kind, params, seed=3).fit(X, dataset.y).predict(X)
    p2 = make_model(kind, params, seed=3).fit(X, dataset.y).predict(X)
    assert np.array_equal(p1, p2)
    assert set(p1) <= set(dataset.y)


@needs_torch
def test_torch_models_learn(dataset):
    X = dataset.inputs("features")
    m = make_model("mlp", {"epochs": 30}).fit(X, dataset.y)
    assert np.mean(m.predict(X) == dataset.y) > 0.9
    assert m.loss_curve_[-1] < m.loss_curve_[0]
    proba = m.predict_proba(X[:4])
    np.testing.assert_allclose(proba.sum(axis=1), 1.0, rtol=1e-5)
    # the CNN reads a 2-D array as one-channel windows; 4-D input is refused
    with pytest.raises(InputError, match="raw windows"):
        make_model("cnn1d", {"epochs": 1}).fit(X[:, :, None, None], dataset.y)


# ------------------------------------------------------------------ artifacts
def _info(ds, kind="linear-ovo-svm"):
    from gaitml.features import feature_names

    return {
        "model_kind": kind,
        "input_kind": "features",
        "feature_set": "all52",
        "feature_names": list(feature_names("all52")),
        "window": {"length_s": 1.5, "overlap": 0.5},
        "sampling_rate_hz": 50.0,
        "labels": sorted(set(ds.y)),
    }


@pytest.fixture
def saved(tmp_path, dataset):
    m = LinearOVOSVM().fit(dataset.inputs("features"), dataset.y)
    save_model(tmp_path / "m", m, _info(dataset))
    return tmp_path / "m"


def test_artifact_roundtrip(saved, dataset):
    info = json.loads((saved / "model.json").read_text())
    for key in ("files", "versions", "feature_names", "window", "sampling_rate_hz", "labels", "security_note", "estimator"):
        assert key in info
    assert {"gaitml", "scikit-learn", "numpy"} <= set(info["versions"])
    assert sorted(p.name for p in saved.iterdir()) == ["MODEL.md", "arrays.npz", "model.json"]
    assert set(info["files"]) == {"arrays.npz"} and info["estimator"]["class"] == "LinearOVOSVM"
    m = load_model(saved)
    X = dataset.inputs("features")
    fresh = LinearOVOSVM().fit(X, dataset.y)
    assert np.array_equal(m.estimator.predict(X), fresh.predict(X))
    np.testing.assert_array_equal(m.estimator.pairwise_decision_function(X), fresh.pairwise_decision_function(X))
    assert m.estimator.get_params() == fresh.get_params()


def test_tampered_bytes_refused(saved):
    p = saved / "arrays.npz"
    b = bytearray(p.read_bytes())
    b[len(b) // 2] ^= 0xFF
    p.write_bytes(bytes(b))
    with pytest.raises(ModelError, match="sha256"):
        load_model(saved)


def _write_rehashed(folder, info):
    """Write an edited model.json with a fresh settings hash (simulates another environment)."""
    from gaitml.models._persist import settings_sha256

    info["settings_sha256"] = settings_sha256(info)
    (folder / "model.json").write_text(json.dumps(info))


@pytest.mark.parametrize(
    ("edit", "match"),
    [
        (lambda i: i["window"].update(length_s=3.0), "model.json was edited"),
        (lambda i: i.update(sampling_rate_hz=100.0), "retrain or restore it"),
        (lambda i: i.update(model_kind="mlp"), "model.json was edited"),
        (lambda i: i.pop("window"), "lacks the required entry window"),
        (lambda i: i["window"].pop("overlap"), "lacks the required entry window.overlap"),
        (lambda i: i.pop("files"), "has no files entry"),
        (lambda i: i["files"].update({"model.joblib": "0" * 64}), "lists the files"),
        (lambda i: i.pop("settings_sha256"), "has no settings_sha256 entry"),
    ],
)
def test_edited_model_json_refused(saved, edit, match):
    info = json.loads((saved / "model.json").read_text())
    edit(info)
    (saved / "model.json").write_text(json.dumps(info, indent=4))
    with pytest.raises(ModelError, match=match):
        load_model(saved)


def test_reformatted_model_json_still_loads(saved):
    info = json.loads((saved / "model.json").read_text())
    (saved / "model.json").write_text(json.dumps(dict(reversed(list(info.items()))), indent=1))
    assert load_model(saved).length_s == 1.5


@needs_torch
def test_torch_kind_without_torch_version_is_explained(saved):
    info = json.loads((saved / "model.json").read_text())
    info["model_kind"] = "mlp"
    _write_rehashed(saved, info)
    with pytest.raises(ModelError, match="records no torch version"):
        load_model(saved)


@pytest.mark.parametrize("lib", ["gaitml", "scikit-learn"])
def test_wrong_version_refused(saved, lib):
    info = json.loads((saved / "model.json").read_text())
    info["versions"][lib] = "0.0.1"
    _write_rehashed(saved, info)
    with pytest.raises(ModelError, match=f"saved with {lib} 0.0.1"):
        load_model(saved)


def test_other_feature_set_refused(saved):
    info = json.loads((saved / "model.json").read_text())
    info["feature_set"] = "paper34"  # names still the 52: the set no longer matches
    _write_rehashed(saved, info)
    with pytest.raises(ModelError, match="feature names do not match feature set 'paper34'"):
        load_model(saved)
    info["feature_names"] = info["feature_names"][:34]
    from gaitml.features import feature_names

    info["feature_names"] = list(feature_names("paper34"))
    _write_rehashed(saved, info)
    with pytest.raises(ModelError, match="takes 52 features but model.json lists 34"):
        load_model(saved)


def test_missing_or_corrupt_artifact(tmp_path, saved):
    with pytest.raises(ModelError, match="not found"):
        load_model(tmp_path / "nope")
    (saved / "model.json").write_text("{not json")
    with pytest.raises(ModelError, match="cannot read"):
        load_model(saved)
    (saved / "model.json").unlink()
    with pytest.raises(ModelError, match="model.json is missing"):
        load_model(saved)


def test_predict_recording_resamples_and_corrects(saved):
    from gaitml.models import resample_recording
    from tests.models.synth import synth_recording

    model = load_model(saved)
    rec = synth_recording(7, seconds_per_mode=10.0)
    out = predict_recording(model, rec)
    assert list(out.columns[:6]) == ["start", "end", "t_start_s", "t_end_s", "mode_raw", "mode"]
    assert np.mean(out["mode"] == out["label"]) > 0.9
    raw = predict_recording(model, rec, correction=False)
    assert np.array_equal(raw["mode"], raw["mode_raw"])
    # the same recording at 100 Hz, without labels: resampled to the model's 50 Hz
    rec100 = resample_recording(rec, 100.0).replace(labels=None)
    out100 = predict_recording(model, rec100)
    assert out100.attrs["resampled_from_hz"] == 100.0
    assert "label" not in out100.columns
    assert abs(len(out100) - len(out)) <= 1
    n = min(len(out), len(out100))
    assert np.mean(out100["mode"].to_numpy()[:n] == out["mode"].to_numpy()[:n]) > 0.9
    with pytest.raises(InputError, match="too short"):
        predict_recording(model, rec.slice(0, 40))


def test_dataset_skips_recordings_shorter_than_a_window_and_counts_drops():
    recs = synth_set(2, seconds_per_mode=6.0)
    short = recs[0].slice(0, 30)
    ds = build_window_dataset([*recs, short], groups=["a", "b", "c"], length_s=1.5, overlap=0.5, keep_labels=["walk", "run"], need_raw=True)
    assert ds.skipped_recordings == [short.name]
    assert set(ds.y) == {"walk", "run"} and ds.dropped_labels.get("side_left", 0) > 0
    assert ds.n_dropped_label == sum(ds.dropped_labels.values())
    assert len(ds) == len(ds.features) == len(ds.raw)
    assert ds.raw.shape[1:] == (75, 4)
    # raw channel 3 is |acc| - g of the window's samples
    w0 = ds.windows.iloc[0]
    r0 = recs[int(w0["recording"])]
    np.testing.assert_allclose(ds.raw[0, :, 3], np.linalg.norm(r0.acc[w0["start"] : w0["end"]], axis=1) - 9.80665)


def test_shipped_gyro_model_on_accelerometer_only_data_names_the_fix(tmp_path, capsys):
    from pathlib import Path

    from gaitml.cli import main
    from gaitml.io import write_gaitml_csv
    from gaitml.recording import Recording

    root = Path(__file__).resolve().parents[2]
    if not (root / "models" / "demo" / "model.json").is_file():
        pytest.skip("models/demo is not trained")
    t = np.arange(500) / 50.0
    acc = np.c_[0.3 * np.sin(2 * np.pi * 2 * t), np.zeros_like(t), 9.81 + np.sin(2 * np.pi * 2 * t)]
    path = tmp_path / "acc_only.csv"
    write_gaitml_csv(Recording.from_arrays(acc, 50.0), path)
    assert main(["predict", str(root / "models" / "demo"), str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "needs a gyroscope" in err and "'all52'" in err and "models/demo-acc" in err
