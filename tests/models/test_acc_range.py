"""The accelerometer range a model reads every phone through (gaitml.features._range, ``[features] acc_range_ms2``).

A model with a range must read the same clipped signal in every path that computes its
features (whole, chunked, streamed, step windows, the JSON export) and in its domain check,
while the fixed physics rules (foot placement, still gate) read the recording as it is. A model
without the key must predict exactly as before. Training with the setting clips the training
recordings and records the key. The "twin" of a shipped model is the same estimator and domain
record with ``acc_range_ms2`` added to its info: what changes is only the range.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pandas as pd
import pytest

from gaitml.errors import ConfigError, InputError
from gaitml.features import StreamingFeatureExtractor, acc_range_tally, check_acc_range, clip_acc, make_windows
from gaitml.models import load_model, model_inputs, predict_recording
from gaitml.models._placement import FOOT_REASON
from gaitml.models._predict import model_view
from gaitml.simulate import simulate_dataset
from gaitml.simulate.foot import simulate_foot
from tests.conftest import ROOT, with_domain_range

DEMO = ROOT / "models" / "demo"
DEMO_ACC = ROOT / "models" / "demo-acc"
RANGE = 19.6  # +-2 g, the range of the Nexus 5 and iPhone 4S


def _load(path):
    """A shipped model with its domain record read as the recording comes (the shipped ``models/demo`` reads
    its check through the 2 g range, ``[train] domain_acc_range_ms2``): the unranged model these tests compare with."""
    return with_domain_range(load_model(path), None)


def _twin(model, range_ms2=RANGE):
    return dataclasses.replace(model, info={**model.info, "acc_range_ms2": range_ms2})


def _vigorous(seed=5, duration_s=40.0):
    """A simulated walk and run in mixed hand poses whose accelerometer goes beyond 2 g on some samples."""
    rec = simulate_dataset(1, duration_s, modes=["run", "walk"], sampling_rate_hz=50.0, seed=seed, pose="mixed")[0]
    assert np.mean(np.abs(rec.acc).max(axis=1) > RANGE) > 0.01  # the test needs samples beyond the range
    return rec


MODEL_COLS = ["mode_raw", "in_domain", "domain_distance", "gravity_angle_deg"]


def test_clip_and_tally():
    acc = np.array([[0.0, 0.0, 9.8], [25.0, -30.0, 9.8], [19.6, -19.6, 0.0], [0.0, 0.0, -40.0]])
    out = clip_acc(acc, RANGE)
    assert np.abs(out).max() <= RANGE and (out[[0, 2]] == acc[[0, 2]]).all()
    np.testing.assert_array_equal(out[1], [RANGE, -RANGE, 9.8])
    t = acc_range_tally(acc, RANGE)
    assert t["n_samples"] == 4 and t["n_samples_clipped"] == 2 and t["max_abs_axis_ms2"] == 40.0 and t["wider"]
    assert clip_acc(acc, None) is not None and (clip_acc(acc, 0) == acc).all()
    assert acc_range_tally(acc, None) is None and check_acc_range(0) is None
    for bad in (5.0, -19.6, float("nan"), "x"):
        with pytest.raises(InputError, match="accelerometer range"):
            check_acc_range(bad)


def test_a_model_without_the_key_predicts_as_before():
    model = _load(DEMO)
    assert model.acc_range_ms2 is None and "acc_range_ms2" not in model.info
    rec = _vigorous()
    view, tally = model_view(model, rec)
    assert view is rec and tally is None
    table = predict_recording(model, rec)
    assert table.attrs["acc_range"] is None
    # a range no sample reaches changes nothing either: the no-key path is the unclipped one
    wide = predict_recording(_twin(model, 1e4), rec)
    assert wide.attrs["acc_range"]["n_samples_clipped"] == 0
    pd.testing.assert_frame_equal(table, wide)


def test_whole_prediction_reads_the_clipped_signal_and_the_rules_read_the_raw_one():
    model = _load(DEMO)
    twin = _twin(model)
    rec = _vigorous()
    clipped = rec.replace(acc=clip_acc(rec.acc, RANGE), check_units=False)
    got = predict_recording(twin, rec)
    want = predict_recording(model, clipped)  # the unranged model on the clipped recording
    for c in MODEL_COLS:
        np.testing.assert_array_equal(got[c].to_numpy(), want[c].to_numpy(), err_msg=c)
    # ... and the clip changed what the model reads (else the test above proves nothing)
    raw = predict_recording(model, rec)
    assert np.nanmax(np.abs(raw["domain_distance"].to_numpy() - got["domain_distance"].to_numpy())) > 1e-6
    # the still gate reads the recording as it is
    np.testing.assert_array_equal(got["still"].to_numpy(), raw["still"].to_numpy())
    t = got.attrs["acc_range"]
    assert t["range_ms2"] == RANGE and t["n_samples"] == rec.n_samples
    assert t["n_samples_clipped"] == int(np.count_nonzero(np.abs(rec.acc).max(axis=1) > RANGE)) > 0


@pytest.mark.parametrize("path", [DEMO, DEMO_ACC])
def test_the_foot_rule_reads_the_raw_accelerometer(path):
    # the accelerometer-only foot test needs peaks of 2.5 g, beyond a 2 g range: it must see them unclipped
    model = _load(path)
    rec = simulate_foot(modes=("walk",), duration_s=40.0, sampling_rate_hz=model.sampling_rate_hz, seed=611)
    if "gyro" not in model.feature_set:
        rec = rec.__class__(acc=rec.acc, sampling_rate_hz=rec.sampling_rate_hz, meta=rec.meta, check_units=False)
    assert np.abs(rec.acc).max() > 2.5 * 9.81 > RANGE
    a = predict_recording(model, rec)
    b = predict_recording(_twin(model), rec)
    foot_a = a["out_of_domain_reason"].to_numpy(dtype=object) == FOOT_REASON
    foot_b = b["out_of_domain_reason"].to_numpy(dtype=object) == FOOT_REASON
    np.testing.assert_array_equal(foot_a, foot_b)
    assert foot_b.mean() >= 0.7
    assert not b["in_domain"].to_numpy(dtype=object)[foot_b].any()


def test_chunked_prediction_equals_whole(tmp_path):
    from gaitml.chunked_run import long_predict
    from gaitml.io import read_recording, write_gaitml_csv

    twin = _twin(_load(DEMO))
    path = tmp_path / "run.csv"
    write_gaitml_csv(_vigorous(seed=7, duration_s=70.0), path)
    rec = read_recording(path)
    whole = predict_recording(twin, rec)
    chunked = long_predict(twin, path, chunk_s=20.0, progress=False)
    assert len(whole) == len(chunked) > 40
    for c in (*MODEL_COLS, "mode", "out_of_domain_reason", "still"):
        assert whole[c].tolist() == chunked[c].tolist() or np.allclose(whole[c], chunked[c], equal_nan=True, rtol=1e-6, atol=1e-9), (
            c
        )  # summation order
    w, c = whole.attrs["acc_range"], chunked.attrs["acc_range"]
    assert c["n_samples"] == w["n_samples"] == rec.n_samples
    assert c["n_samples_clipped"] == w["n_samples_clipped"] > 0 and c["max_abs_axis_ms2"] == w["max_abs_axis_ms2"]


def test_streamed_rows_equal_the_whole_file_rows():
    twin = _twin(_load(DEMO))
    rec = _vigorous(seed=9)
    ext = StreamingFeatureExtractor.for_model(twin)
    assert ext.acc_range_ms2 == RANGE
    rows, starts = [], []
    hop = ext.hop_samples_
    for i in range(0, rec.n_samples, hop):
        r = ext.push(rec.acc[i : i + hop], rec.gyr[i : i + hop])
        rows.append(r)
        starts.extend(ext.last_starts_.tolist())
    X_stream = np.vstack(rows)
    w = make_windows(rec, twin.length_s, twin.overlap, min_label_fraction=0.0).reset_index(drop=True)
    assert starts == w["start"].tolist()
    X_whole = model_inputs(twin, model_view(twin, rec)[0], w)
    np.testing.assert_allclose(X_stream, X_whole, rtol=1e-9, atol=1e-9)
    assert ext.n_clipped_ == acc_range_tally(rec.acc, RANGE)["n_samples_clipped"] > 0
    # the streamed classes are the whole-file path's
    whole = predict_recording(twin, rec, correction=False)
    assert [str(v) for v in twin.estimator.predict(X_stream)] == whole["mode_raw"].tolist()
    # without the range the rows differ (the clip matters here)
    plain = StreamingFeatureExtractor.for_model(_load(DEMO))
    assert plain.acc_range_ms2 is None
    assert not np.allclose(plain.push(rec.acc, rec.gyr), X_whole)


def test_json_export_carries_the_range_and_a_plain_reader_reproduces_predict(tmp_path):
    from gaitml.models import export_json
    from gaitml.models._export import PORTABLE_FORMAT_VERSION, PORTABLE_RANGE_FORMAT_VERSION
    from tests.models.test_persist import _numpy_predict_from_json

    model = _load(DEMO)
    plain = export_json(model)
    assert plain["format_version"] == PORTABLE_FORMAT_VERSION and "acc_range" not in plain
    twin = _twin(model)
    spec = json.loads(json.dumps(export_json(twin)))
    assert spec["format_version"] == PORTABLE_RANGE_FORMAT_VERSION >= 3  # acc_range is new in 3
    assert spec["acc_range"]["range_ms2"] == RANGE and "clip each accelerometer axis" in spec["acc_range"]["rule"]
    rec = _vigorous(seed=11)
    r = spec["acc_range"]["range_ms2"]
    raw_modes, corrected, _ = _numpy_predict_from_json(spec, np.clip(rec.acc, -r, r), rec.gyr)
    table = predict_recording(twin, rec)
    np.testing.assert_array_equal(raw_modes, table["mode_raw"].to_numpy())
    # the plain reader's still gate read the clipped signal: compare where the gate did not fire
    moving = ~table["still"].to_numpy(bool)
    np.testing.assert_array_equal(corrected[moving], table["mode"].to_numpy()[moving])


def test_predict_command_reports_the_range(tmp_path, capsys):
    from gaitml.cli import main
    from gaitml.io import write_gaitml_csv
    from gaitml.models import save_model

    model = _load(DEMO)
    info = {k: v for k, v in model.info.items() if k not in ("domain",)}
    save_model(tmp_path / "m", model.estimator, {**info, "acc_range_ms2": RANGE}, domain=model.domain, card=False)
    assert load_model(tmp_path / "m").acc_range_ms2 == RANGE
    rec = _vigorous()
    write_gaitml_csv(rec, tmp_path / "r.csv")
    assert main(["predict", str(tmp_path / "m"), str(tmp_path / "r.csv"), "--json"]) == 0
    out = capsys.readouterr()
    res = json.loads(out.out)
    assert res["acc_range"]["range_ms2"] == RANGE and res["acc_range"]["n_samples_clipped"] > 0
    assert res["acc_range"]["wider"] and out.err.count("beyond the model's range") == 1
    # a phone that clips near the range itself: no warning line
    calm = rec.replace(acc=np.clip(rec.acc, -21.0, 21.0), check_units=False)
    write_gaitml_csv(calm, tmp_path / "c.csv")
    assert main(["predict", str(tmp_path / "m"), str(tmp_path / "c.csv"), "--json"]) == 0
    out = capsys.readouterr()
    assert json.loads(out.out)["acc_range"]["wider"] is False and "beyond the model's range" not in out.err
    # a model without the key says so as null
    assert main(["predict", str(DEMO), str(tmp_path / "c.csv"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["acc_range"] is None


def test_training_with_a_range_clips_the_training_set_and_records_it(tmp_path):
    from gaitml.pipeline import parse_config, prepare_data, train_config

    raw = {
        "name": "ranged",
        "seed": 1,
        "data": {"source": "simulated", "simulated": {"subjects": 2, "duration_s": 40.0, "modes": ["walk", "run"]}},
        "features": {"set": "all52+gyro", "acc_range_ms2": RANGE},
        "train": {"cross_validate": False},
    }
    cfg = parse_config(raw)
    data = prepare_data(cfg)
    assert max(float(np.abs(r.acc).max()) for r in data.recordings) <= RANGE
    assert any("read through +-19.6 m/s^2" in n for n in data.notes)
    model = train_config(cfg, out_dir=tmp_path / "m", progress=False)
    loaded = load_model(tmp_path / "m")
    assert loaded.acc_range_ms2 == RANGE == model.acc_range_ms2
    # off by default: no key, the recordings as they came
    plain_cfg = parse_config({**raw, "features": {"set": "all52+gyro"}})
    assert plain_cfg["features"]["acc_range_ms2"] == 0
    plain = prepare_data(plain_cfg)
    assert max(float(np.abs(r.acc).max()) for r in plain.recordings) > RANGE
    assert not any("read through" in n for n in plain.notes)
    with pytest.raises(ConfigError, match="acc_range_ms2"):
        parse_config({**raw, "features": {"acc_range_ms2": 5.0}})


def test_step_window_model_reads_the_range(tmp_path):
    from gaitml.models import predict_step_windows
    from gaitml.pipeline import parse_config, train_config

    cfg = parse_config(
        {
            "name": "steps-ranged",
            "data": {"simulated": {"subjects": 2, "duration_s": 30.0, "modes": ["walk", "run"]}},
            "windows": {"by": "steps"},
            "features": {"acc_range_ms2": RANGE},
            "train": {"cross_validate": False},
        }
    )
    model = load_model(train_config(cfg, out_dir=tmp_path / "m", progress=False).path)
    rec = _vigorous(seed=13, duration_s=30.0)
    got = predict_step_windows(model, rec)
    plain = dataclasses.replace(model, info={k: v for k, v in model.info.items() if k != "acc_range_ms2"})
    want = predict_step_windows(plain, rec.replace(acc=clip_acc(rec.acc, RANGE), check_units=False))
    assert len(got) == len(want) > 10
    for c in MODEL_COLS:
        np.testing.assert_array_equal(got[c].to_numpy(), want[c].to_numpy(), err_msg=c)
    assert got.attrs["acc_range"]["n_samples_clipped"] > 0
