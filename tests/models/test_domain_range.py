"""The domain record read through an accelerometer range while the classifier is not (``[train] domain_acc_range_ms2``).

A record with its own range (``DomainModel.acc_range_ms2``) computes the check's features,
gravity direction and orientation dynamics on the recording clipped per axis to that range,
in training and in every prediction path; the classifier's inputs, its modes and the fixed
physics rules (foot placement, still gate) read the recording as it is. The "twin" of the
shipped model is the same estimator and record with ``acc_range_ms2`` set on the record.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import ConfigError, InputError, ModelError
from gaitml.features import StreamingFeatureExtractor, clip_acc
from gaitml.models import load_model, predict_recording
from gaitml.models._placement import FOOT_REASON
from gaitml.models.domain import DomainModel, feature_gravity
from gaitml.simulate import simulate_dataset
from gaitml.simulate.foot import simulate_foot
from tests.conftest import ROOT, with_domain_range

DEMO = ROOT / "models" / "demo"
RANGE = 19.6  # +-2 g, the range of the Nexus 5 and iPhone 4S
DOMAIN_COLS = ["domain_distance", "gravity_angle_deg", "dynamics_distance"]
CLASSIFIER_COLS = ["mode_raw", "mode", "still"]


def _plain(path=DEMO):
    """The shipped model with its record read as the recording comes (``acc_range_ms2`` None): the twin's base."""
    return with_domain_range(load_model(path), None)


def test_the_shipped_demo_reads_its_check_through_the_2g_range():
    assert load_model(DEMO).domain.acc_range_ms2 == RANGE and load_model(DEMO).acc_range_ms2 is None


def _dom_twin(model, range_ms2=RANGE):
    return with_domain_range(model, range_ms2)


def _vigorous(seed=5, duration_s=40.0):
    """A simulated walk and run in mixed hand poses whose accelerometer goes beyond 2 g on some samples."""
    rec = simulate_dataset(1, duration_s, modes=["run", "walk"], sampling_rate_hz=50.0, seed=seed, pose="mixed")[0]
    assert np.mean(np.abs(rec.acc).max(axis=1) > RANGE) > 0.01  # the test needs samples beyond the range
    return rec


def _clipped(rec):
    return rec.replace(acc=clip_acc(rec.acc, RANGE), check_units=False)


def test_the_check_reads_the_clipped_signal_and_the_classifier_the_raw_one():
    model = _plain()
    assert model.domain.acc_range_ms2 is None
    twin = _dom_twin(model)
    rec = _vigorous()
    got = predict_recording(twin, rec)
    raw = predict_recording(model, rec)
    clip = predict_recording(model, _clipped(rec))  # the plain model on the clipped recording
    for c in CLASSIFIER_COLS:
        np.testing.assert_array_equal(got[c].to_numpy(), raw[c].to_numpy(), err_msg=c)
    for c in DOMAIN_COLS:
        np.testing.assert_allclose(got[c].to_numpy(float), clip[c].to_numpy(float), rtol=1e-9, atol=1e-12, err_msg=c)
    foot = got["out_of_domain_reason"].to_numpy(dtype=object) == FOOT_REASON
    np.testing.assert_array_equal(foot, raw["out_of_domain_reason"].to_numpy(dtype=object) == FOOT_REASON)
    keep = ~foot & (clip["out_of_domain_reason"].to_numpy(dtype=object) != FOOT_REASON)
    np.testing.assert_array_equal(got["in_domain"].to_numpy()[keep], clip["in_domain"].to_numpy()[keep])
    # the clip changed what the check reads and not what the classifier reads (else the test proves nothing)
    assert np.nanmax(np.abs(raw["domain_distance"].to_numpy() - got["domain_distance"].to_numpy())) > 1e-6


def test_the_check_recomputes_only_the_windows_holding_a_clipped_sample():
    """The shipped model's check reuses the classifier's rows for the windows without a sample beyond the record's
    range and recomputes the rest on the clipped recording: the same columns as computing the record's features of
    every window on the clipped recording."""
    from gaitml.features import features_from_arrays
    from gaitml.models._predict import (
        _windows_for,
        checked_domain_columns,
        domain_columns,
        model_inputs,
        recording_dynamics,
        windows_with_changed_samples,
    )

    model = load_model(DEMO)
    dom = model.domain
    rec = simulate_dataset(1, 60.0, modes=["run", "walk"], sampling_rate_hz=50.0, seed=8, pose="mixed")[0]
    w = _windows_for(rec, model.length_s, model.overlap)
    starts = w["start"].to_numpy(np.int64)
    length = int(round(model.length_s * model.sampling_rate_hz))
    clip = _clipped(rec)
    rows = windows_with_changed_samples(rec.acc, clip.acc, starts, length)
    assert 0 < rows.sum() < len(rows) - 5  # both kinds of window (else one path is not exercised)
    fast = domain_columns(model, rec, w, model_inputs(model, rec, w))
    X = features_from_arrays(clip.acc, clip.gyr, clip.sampling_rate_hz, starts, length, dom.feature_set, dom.frame)
    slow = checked_domain_columns(dom, X, feature_gravity(X, dom.feature_names), recording_dynamics(dom, clip, starts, starts + length))
    assert set(fast) == set(slow)
    np.testing.assert_array_equal(fast["in_domain"], slow["in_domain"])
    for c in ("domain_distance", "gravity_angle_deg", "dynamics_distance"):
        np.testing.assert_allclose(fast[c], slow[c], rtol=1e-12, atol=1e-12, equal_nan=True, err_msg=c)


def test_windows_with_changed_samples_are_those_holding_one():
    from gaitml.models._predict import windows_with_changed_samples

    acc = np.zeros((10, 3))
    acc[8] = np.nan  # NaN in both: counted as changed (the window is recomputed, never wrongly reused)
    seen = acc.copy()
    seen[4, 2] = 1.0
    got = windows_with_changed_samples(acc, seen, np.array([0, 2, 5, 7]), 3)
    np.testing.assert_array_equal(got, [False, True, False, True])
    assert not windows_with_changed_samples(acc, acc, np.array([0, 5]), 3).any()


def test_a_range_no_sample_reaches_changes_nothing():
    model = _plain()
    rec = _vigorous(seed=6)
    pd.testing.assert_frame_equal(predict_recording(model, rec), predict_recording(_dom_twin(model, 1e4), rec))


def test_the_foot_rule_reads_the_raw_accelerometer():
    model = _plain()
    rec = simulate_foot(modes=("walk",), duration_s=40.0, sampling_rate_hz=model.sampling_rate_hz, seed=611)
    assert np.abs(rec.acc).max() > 2.5 * 9.81 > RANGE
    a = predict_recording(model, rec)
    b = predict_recording(_dom_twin(model), rec)
    foot_a = a["out_of_domain_reason"].to_numpy(dtype=object) == FOOT_REASON
    foot_b = b["out_of_domain_reason"].to_numpy(dtype=object) == FOOT_REASON
    np.testing.assert_array_equal(foot_a, foot_b)
    assert foot_b.mean() >= 0.7 and not b["in_domain"].to_numpy(dtype=object)[foot_b].any()


def test_chunked_prediction_equals_whole(tmp_path):
    from gaitml.chunked_run import long_predict
    from gaitml.io import read_recording, write_gaitml_csv

    twin = _dom_twin(_plain())
    path = tmp_path / "run.csv"
    write_gaitml_csv(_vigorous(seed=7, duration_s=70.0), path)
    rec = read_recording(path)
    whole = predict_recording(twin, rec)
    chunked = long_predict(twin, path, chunk_s=20.0, progress=False)
    assert len(whole) == len(chunked) > 40
    for c in ("mode_raw", "mode", "in_domain", "out_of_domain_reason", "still", *DOMAIN_COLS):
        a, b = whole[c], chunked[c]
        assert a.tolist() == b.tolist() or np.allclose(a.to_numpy(float), b.to_numpy(float), equal_nan=True, rtol=1e-6, atol=1e-9), c


def test_streamed_domain_rows_give_the_whole_file_check():
    model = _plain()
    twin = _dom_twin(model)
    rec = _vigorous(seed=9)
    ext = StreamingFeatureExtractor.for_domain(twin)
    assert ext.acc_range_ms2 == RANGE and StreamingFeatureExtractor.for_domain(model).acc_range_ms2 is None
    rows = [
        ext.push(rec.acc[i : i + ext.hop_samples_], rec.gyr[i : i + ext.hop_samples_]) for i in range(0, rec.n_samples, ext.hop_samples_)
    ]
    X = np.vstack(rows)
    g = feature_gravity(X, twin.domain.feature_names)
    one = [twin.domain.check(X[i : i + 1], g[i : i + 1])["distance"][0] for i in range(len(X))]
    whole = predict_recording(twin, rec)
    np.testing.assert_allclose(one, whole["domain_distance"].to_numpy(float), rtol=1e-9)
    # the classifier's stream reads the raw signal: its rows differ from the domain's here
    assert not np.allclose(StreamingFeatureExtractor.for_model(twin).push(rec.acc, rec.gyr), X)
    with pytest.raises(InputError, match="no domain record"):
        StreamingFeatureExtractor.for_domain(dataclasses.replace(model, domain=None))


def test_the_record_keeps_its_range_and_refuses_a_bad_one():
    dom = _dom_twin(_plain()).domain
    info, arrays = dom.to_json(), dom.to_arrays()
    assert info["acc_range_ms2"] == RANGE
    assert DomainModel.from_json(info, arrays).acc_range_ms2 == RANGE
    plain = _plain().domain.to_json()
    assert "acc_range_ms2" not in plain and DomainModel.from_json(plain, arrays).acc_range_ms2 is None
    for bad in (5.0, "x", -19.6):
        with pytest.raises(ModelError, match="acc_range_ms2"):
            DomainModel.from_json({**info, "acc_range_ms2": bad}, arrays)


def _cfg(**over):
    from gaitml.pipeline import parse_config

    raw = {
        "name": "domain-ranged",
        "seed": 1,
        "data": {"source": "simulated", "simulated": {"subjects": 2, "duration_s": 40.0, "modes": ["walk", "run"]}},
        "features": {"set": "all52+gyro"},
        "train": {"cross_validate": False},
    }
    for k, v in over.items():
        raw[k] = {**raw.get(k, {}), **v}
    return parse_config(raw)


def test_training_fits_the_record_through_the_range_and_the_classifier_without_it(tmp_path):
    from gaitml.pipeline import train_config

    assert _cfg()["train"]["domain_acc_range_ms2"] == 0 and "domain_acc_range_ms2" not in _cfg().resolved()["train"]
    with pytest.raises(ConfigError, match="domain_acc_range_ms2"):
        _cfg(train={"domain_acc_range_ms2": 5.0})
    with pytest.raises(ConfigError, match="range the domain record alone"):
        _cfg(train={"domain_acc_range_ms2": RANGE}, features={"acc_range_ms2": RANGE})
    plain = load_model(train_config(_cfg(), out_dir=tmp_path / "plain", progress=False).path)
    dom = load_model(train_config(_cfg(train={"domain_acc_range_ms2": RANGE}), out_dir=tmp_path / "dom", progress=False).path)
    full = load_model(train_config(_cfg(features={"acc_range_ms2": RANGE}), out_dir=tmp_path / "full", progress=False).path)
    assert dom.acc_range_ms2 is None and dom.domain.acc_range_ms2 == RANGE and plain.domain.acc_range_ms2 is None
    # the classifier is the unranged one; the record is the one the fully ranged model fits (the same clipped windows)
    for k in ("coef_", "intercept_"):
        np.testing.assert_array_equal(getattr(dom.estimator, k), getattr(plain.estimator, k), err_msg=k)
    for k, a in full.domain.arrays.items():
        np.testing.assert_allclose(dom.domain.arrays[k], a, rtol=1e-7, atol=1e-9 * np.abs(a).max(), err_msg=k)
    assert dom.domain.distance_threshold == pytest.approx(full.domain.distance_threshold, rel=1e-9)
    assert not np.allclose(dom.domain.arrays["center"], plain.domain.arrays["center"])
    assert "Accelerometer range of the check" in (tmp_path / "dom" / "MODEL.md").read_text()
    rec = _vigorous(seed=11)
    a, b = predict_recording(dom, rec), predict_recording(plain, rec)
    np.testing.assert_array_equal(a["mode_raw"].to_numpy(), b["mode_raw"].to_numpy())
    c = predict_recording(full, _clipped(rec))
    np.testing.assert_allclose(a["domain_distance"].to_numpy(float), c["domain_distance"].to_numpy(float), rtol=1e-6)


def test_step_window_model_reads_the_check_through_the_range(tmp_path):
    from gaitml.models import predict_step_windows
    from gaitml.pipeline import parse_config, train_config

    cfg = parse_config(
        {
            "name": "steps-domain-ranged",
            "data": {"simulated": {"subjects": 2, "duration_s": 30.0, "modes": ["walk", "run"]}},
            "windows": {"by": "steps"},
            "train": {"cross_validate": False, "domain_acc_range_ms2": RANGE},
        }
    )
    model = load_model(train_config(cfg, out_dir=tmp_path / "m", progress=False).path)
    assert model.domain.acc_range_ms2 == RANGE
    rec = _vigorous(seed=13, duration_s=30.0)
    from gaitml.models._step_windows import step_domain_columns

    got = predict_step_windows(model, rec)
    plain = with_domain_range(model, None)
    raw = predict_step_windows(plain, rec)
    # the steps are found on the recording as it is: the plain record on the clipped recording, over the same spans
    clip = pd.DataFrame(step_domain_columns(plain, _clipped(rec), got[["start", "end"]].reset_index(drop=True)))
    assert len(got) == len(raw) > 10
    np.testing.assert_array_equal(got["mode_raw"].to_numpy(), raw["mode_raw"].to_numpy())
    np.testing.assert_allclose(got["domain_distance"].to_numpy(float), clip["domain_distance"].to_numpy(float), rtol=1e-9)
    assert np.nanmax(np.abs(got["domain_distance"].to_numpy(float) - raw["domain_distance"].to_numpy(float))) > 1e-6
